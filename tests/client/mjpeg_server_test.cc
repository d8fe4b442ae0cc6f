// MjpegServer over real sockets on 127.0.0.1 (ephemeral ports), with real JPEGs from OpenCV.
#include "client/mjpeg_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/check.h"
#include "tests/common/eventually.h"

namespace viscera::client {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

// A blocking test client; every read gives up after 10 s so that a bug fails, not hangs.
class Client {
 public:
  /// `from`: the source address (another loopback address is another peer), or null.
  explicit Client(int port, const char* from = nullptr) {
    fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const timeval timeout{10, 0};
    setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
    if (from != nullptr) {
      sockaddr_in source{};
      source.sin_family = AF_INET;
      inet_pton(AF_INET, from, &source.sin_addr);
      bind(fd_, reinterpret_cast<sockaddr*>(&source), sizeof(source));
    }
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0;
  }
  ~Client() { Close(); }
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  bool connected() const { return connected_; }
  void Close() {
    if (fd_ >= 0) close(fd_);
    fd_ = -1;
  }
  bool Send(const std::string& data) {
    return send(fd_, data.data(), data.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(data.size());
  }
  /// Everything up to and including `delimiter` ("" if it never came).
  std::string ReadUntil(const std::string& delimiter) {
    size_t at;
    while ((at = buffer_.find(delimiter)) == std::string::npos) {
      if (!Fill()) return "";
    }
    return Take(at + delimiter.size());
  }
  /// Exactly n bytes ("" if they never came).
  std::string Read(size_t n) {
    while (buffer_.size() < n) {
      if (!Fill()) return "";
    }
    return Take(n);
  }
  /// Everything until the server closes; nullopt if it did not within the read timeout.
  std::optional<std::string> ReadToEnd() {
    while (true) {
      char chunk[65536];
      const ssize_t n = recv(fd_, chunk, sizeof(chunk), 0);
      if (n == 0) return Take(buffer_.size());
      if (n < 0) return std::nullopt;
      buffer_.append(chunk, static_cast<size_t>(n));
    }
  }

 private:
  bool Fill() {
    char chunk[65536];
    const ssize_t n = recv(fd_, chunk, sizeof(chunk), 0);
    if (n <= 0) return false;
    buffer_.append(chunk, static_cast<size_t>(n));
    return true;
  }
  std::string Take(size_t n) {
    std::string taken = buffer_.substr(0, n);
    buffer_.erase(0, n);
    return taken;
  }

  int fd_ = -1;
  bool connected_ = false;
  std::string buffer_;
};

std::string Request(const std::string& method, const std::string& path) {
  return method + " " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nUser-Agent: test\r\n\r\n";
}

/// The whole response to `request`.
std::string Fetch(int port, const std::string& request) {
  Client client(port);
  EXPECT_TRUE(client.connected());
  EXPECT_TRUE(client.Send(request));
  return client.ReadToEnd().value_or("(no end)");
}
std::string Get(int port, const std::string& path) { return Fetch(port, Request("GET", path)); }

int StatusOf(const std::string& response) {
  if (response.rfind("HTTP/1.0 ", 0) != 0 || response.size() < 12) return -1;
  return std::stoi(response.substr(9, 3));
}
std::string BodyOf(const std::string& response) {
  const size_t end = response.find("\r\n\r\n");
  return end == std::string::npos ? "" : response.substr(end + 4);
}
bool HasField(const std::string& head, const std::string& field) {
  return head.find("\r\n" + field + "\r\n") != std::string::npos;
}

/// Opens /stream.mjpg; returns the response head.
std::string OpenStream(Client* client) {
  EXPECT_TRUE(client->connected());
  EXPECT_TRUE(client->Send(Request("GET", "/stream.mjpg")));
  return client->ReadUntil("\r\n\r\n");
}

/// Reads one part of a stream whose boundary is `boundary`: its JPEG bytes, by its
/// Content-Length ("" on any error, with a failure).
std::string ReadPart(Client* client, const std::string& boundary) {
  const std::string head = client->ReadUntil("\r\n\r\n");
  EXPECT_EQ(head.rfind("--" + boundary + "\r\n", 0), 0u) << head;
  EXPECT_NE(head.find("\r\nContent-Type: image/jpeg\r\n"), std::string::npos) << head;
  const std::string key = "\r\nContent-Length: ";
  const size_t at = head.find(key);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no Content-Length in " << head;
    return "";
  }
  const size_t length = std::stoul(head.substr(at + key.size()));
  std::string jpeg = client->Read(length);
  EXPECT_EQ(client->Read(2), "\r\n");
  return jpeg;
}

std::string BoundaryOf(const std::string& stream_head) {
  const std::string key = "multipart/x-mixed-replace; boundary=";
  const size_t at = stream_head.find(key);
  if (at == std::string::npos) return "";
  return stream_head.substr(at + key.size(), stream_head.find("\r\n", at) - at - key.size());
}

std::vector<uint8_t> Encode(const cv::Mat& image) {
  std::vector<uint8_t> jpeg;
  EXPECT_TRUE(cv::imencode(".jpg", image, jpeg));
  return jpeg;
}
std::vector<uint8_t> SolidJpeg(const cv::Scalar& bgr, int width = 64, int height = 48) {
  return Encode(cv::Mat(height, width, CV_8UC3, bgr));
}
/// Noise compresses badly: a big frame (about 0.5 MB) that fills socket buffers fast.
std::vector<uint8_t> NoiseJpeg(uint64_t seed) {
  cv::Mat image(480, 640, CV_8UC3);
  cv::RNG rng(seed);
  rng.fill(image, cv::RNG::UNIFORM, 0, 256);
  return Encode(image);
}
std::string AsString(const std::vector<uint8_t>& bytes) { return {bytes.begin(), bytes.end()}; }

/// Decodes `jpeg` and checks its size and mean colour (JPEG is lossy: within 8 levels).
void ExpectPicture(const std::string& jpeg, int width, int height, const cv::Scalar& bgr) {
  const std::vector<uint8_t> bytes(jpeg.begin(), jpeg.end());
  const cv::Mat image = cv::imdecode(bytes, cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty()) << "not a JPEG (" << jpeg.size() << " bytes)";
  EXPECT_EQ(image.cols, width);
  EXPECT_EQ(image.rows, height);
  const cv::Scalar mean = cv::mean(image);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], bgr[c], 8.0) << "channel " << c;
}

/// Waits (up to 10 s) until `done`; false if it never was.
bool WaitUntil(const std::function<bool()>& done) {
  const Clock::time_point deadline = Clock::now() + 10s;
  while (!done()) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(5ms);
  }
  return true;
}

const cv::Scalar kRed(0, 0, 255), kBlue(255, 0, 0), kGreen(0, 255, 0);

TEST(ParseHostPort, AcceptsDottedQuadsAndLocalhost) {
  std::string host;
  int port = -1;
  ParseHostPort("127.0.0.1:8080", &host, &port);
  EXPECT_EQ(host, "127.0.0.1");
  EXPECT_EQ(port, 8080);
  ParseHostPort("localhost:0", &host, &port);
  EXPECT_EQ(host, "localhost");
  EXPECT_EQ(port, 0);
  ParseHostPort("0.0.0.0:65535", &host, &port);
  EXPECT_EQ(port, 65535);
}

TEST(ParseHostPort, RejectsBadAddressesSayingWhy) {
  std::string host;
  int port = 0;
  const auto message = [&](const std::string& text) -> std::string {
    try {
      ParseHostPort(text, &host, &port);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(accepted)";
  };
  EXPECT_NE(message("1.2.3:80").find("host '1.2.3'"), std::string::npos) << message("1.2.3:80");
  EXPECT_NE(message("127.0.0.1:99999").find("port '99999'"), std::string::npos);
  EXPECT_NE(message(":80").find("host ''"), std::string::npos) << message(":80");
  EXPECT_NE(message("127.0.0.1").find("not HOST:PORT"), std::string::npos);
  EXPECT_NE(message("127.0.0.1:").find("port ''"), std::string::npos);
  EXPECT_NE(message("127.0.0.1:8o").find("port '8o'"), std::string::npos);
  EXPECT_NE(message("127.0.0.1:-1").find("port '-1'"), std::string::npos);
  EXPECT_NE(message("example.com:80").find("neither"), std::string::npos);
}

TEST(MjpegServer, RejectsBadHostsAndBusyPortsSayingWhy) {
  EXPECT_THROW(MjpegServer("1.2.3", 0, "x"), InputError);
  EXPECT_THROW(MjpegServer("127.0.0.1", 70000, "x"), InputError);
  MjpegServer first("127.0.0.1", 0, "first");
  EXPECT_GT(first.port(), 0);
  try {
    MjpegServer second("127.0.0.1", first.port(), "second");
    ADD_FAILURE() << "bound a port in use";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot bind 127.0.0.1:" + std::to_string(first.port())),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("in use"), std::string::npos) << e.what();
  }
  MjpegServer by_name("localhost", 0, "by name");
  EXPECT_EQ(StatusOf(Get(by_name.port(), "/")), 200);
}

TEST(MjpegServer, PageShowsTheStreamUnderItsEscapedTitle) {
  MjpegServer server("127.0.0.1", 0, "session <7> & co");
  const std::string response = Get(server.port(), "/");
  EXPECT_EQ(StatusOf(response), 200) << response;
  EXPECT_TRUE(HasField(response, "Content-Type: text/html; charset=utf-8"));
  const std::string page = BodyOf(response);
  EXPECT_NE(page.find("img.src = 'stream.mjpg'"), std::string::npos);
  EXPECT_NE(page.find("<script src=\"viewer.js\"></script>"), std::string::npos);
  EXPECT_NE(page.find("<span id=\"shown\">0</span>"), std::string::npos);
  EXPECT_NE(page.find("<title>session &lt;7&gt; &amp; co</title>"), std::string::npos);
  EXPECT_NE(page.find("document.title = title + ' - ' + count + ' frames'"), std::string::npos);
  EXPECT_EQ(BodyOf(Get(server.port(), "/index.html")), page);
  // a query string (a cache buster, say) names the same page
  EXPECT_EQ(BodyOf(Get(server.port(), "/?t=1")), page);

  const std::string head = Fetch(server.port(), Request("HEAD", "/"));
  EXPECT_EQ(StatusOf(head), 200);
  EXPECT_TRUE(HasField(head, "Content-Length: " + std::to_string(page.size()))) << head;
  EXPECT_EQ(BodyOf(head), "");
}

TEST(MjpegServer, StreamsEachNewFrameAsAJpegPart) {
  MjpegServer server("127.0.0.1", 0, "t");
  Client client(server.port());
  const std::string head = OpenStream(&client);
  EXPECT_EQ(head.rfind("HTTP/1.0 200 OK\r\n", 0), 0u) << head;
  EXPECT_TRUE(HasField(head, "Cache-Control: no-cache")) << head;
  EXPECT_TRUE(HasField(head, "Connection: close")) << head;
  const std::string boundary = BoundaryOf(head);
  ASSERT_FALSE(boundary.empty()) << head;

  server.PostFrame(SolidJpeg(kRed, 64, 48));
  ExpectPicture(ReadPart(&client, boundary), 64, 48, kRed);
  server.PostFrame(SolidJpeg(kBlue, 80, 60));
  // the red frame may come once more first (a frame with no successor is repeated)
  std::string part = ReadPart(&client, boundary);
  if (part == AsString(SolidJpeg(kRed, 64, 48))) part = ReadPart(&client, boundary);
  ExpectPicture(part, 80, 60, kBlue);

  // the stream's thread counts a part after sending it: the client may read it first
  EXPECT_TRUE(viscera::testing::Eventually([&] { return server.stats().parts_sent >= 2; }));
  const MjpegServerStats stats = server.stats();
  EXPECT_EQ(stats.frames_posted, 2);
  EXPECT_GE(stats.parts_sent, 2);
  EXPECT_EQ(stats.streams_opened, 1);
  EXPECT_EQ(stats.active_streams, 1);
}

TEST(MjpegServer, AStreamOpenedLaterGetsTheLatestFrameAtOnce) {
  MjpegServer server("127.0.0.1", 0, "t");
  server.PostFrame(SolidJpeg(kRed));
  server.PostFrame(SolidJpeg(kGreen));
  Client client(server.port());
  const std::string boundary = BoundaryOf(OpenStream(&client));
  EXPECT_EQ(ReadPart(&client, boundary), AsString(SolidJpeg(kGreen)));
}

TEST(MjpegServer, AFrameWithNoSuccessorIsSentOnceMoreOnly) {
  // Chromium shows a part when the next part begins: the repeat puts the last frame on screen.
  MjpegServer server("127.0.0.1", 0, "t");
  server.PostFrame(SolidJpeg(kBlue));
  Client client(server.port());
  const std::string boundary = BoundaryOf(OpenStream(&client));
  EXPECT_EQ(ReadPart(&client, boundary), AsString(SolidJpeg(kBlue)));
  EXPECT_EQ(ReadPart(&client, boundary), AsString(SolidJpeg(kBlue)));
  // no third blue part: the stream is in order, so the next part is the next frame posted
  server.PostFrame(SolidJpeg(kRed));
  EXPECT_EQ(ReadPart(&client, boundary), AsString(SolidJpeg(kRed)));
  // (the server counts a part after its last byte went out: the reader may be first)
  EXPECT_TRUE(viscera::testing::Eventually([&] { return server.stats().parts_sent >= 3; }));
  EXPECT_EQ(server.stats().parts_sent, 3);
}

TEST(MjpegServer, ASlowReaderBlocksNeitherPostFrameNorOtherStreams) {
  MjpegServer server("127.0.0.1", 0, "t");
  Client slow(server.port());
  ASSERT_FALSE(OpenStream(&slow).empty());  // then reads nothing for a while
  Client reader(server.port());
  const std::string boundary = BoundaryOf(OpenStream(&reader));
  ASSERT_TRUE(WaitUntil([&] { return server.stats().active_streams == 2; }));

  // the other stream reads all along, until the last frame
  const std::string last = AsString(SolidJpeg(kGreen, 32, 24));
  int reader_parts = 0;
  std::thread reading([&] {
    while (reader_parts < 1000 && ReadPart(&reader, boundary) != last) ++reader_parts;
  });

  // 200 frames of about 0.5 MB: far more than the slow reader's socket buffers hold, so
  // its stream thread soon blocks in send while the frames keep coming
  std::vector<std::vector<uint8_t>> noise;
  for (uint64_t seed = 1; seed <= 8; ++seed) noise.push_back(NoiseJpeg(seed));
  for (int i = 0; i < 200; ++i) {
    server.PostFrame(noise[i % noise.size()]);
    std::this_thread::sleep_for(1ms);
  }
  server.PostFrame(SolidJpeg(kGreen, 32, 24));
  EXPECT_EQ(server.stats().frames_posted, 201);
  reading.join();
  EXPECT_LT(reader_parts, 1000);  // it got the latest frame
  EXPECT_GT(reader_parts, 0);

  // the slow reader, reading at last, skipped frames instead of queueing them all
  int slow_parts = 1;
  while (slow_parts < 1000 && ReadPart(&slow, boundary) != last) ++slow_parts;
  EXPECT_LT(slow_parts, 201);
}

TEST(MjpegServer, AClientLeavingMidStreamLeavesTheOthersServed) {
  MjpegServer server("127.0.0.1", 0, "t");
  auto leaving = std::make_unique<Client>(server.port());
  Client staying(server.port());
  const std::string boundary = BoundaryOf(OpenStream(leaving.get()));
  ASSERT_FALSE(OpenStream(&staying).empty());
  server.PostFrame(NoiseJpeg(1));
  EXPECT_EQ(ReadPart(leaving.get(), boundary), AsString(NoiseJpeg(1)));
  EXPECT_EQ(ReadPart(&staying, boundary), AsString(NoiseJpeg(1)));
  // gone with unread data: the server's next sends fail with ECONNRESET or EPIPE
  leaving->Close();
  for (uint64_t seed = 2; seed < 12; ++seed) server.PostFrame(NoiseJpeg(seed));
  server.PostFrame(SolidJpeg(kRed));

  std::string part;
  for (int i = 0; i < 30 && part != AsString(SolidJpeg(kRed)); ++i)
    part = ReadPart(&staying, boundary);
  EXPECT_EQ(part, AsString(SolidJpeg(kRed)));
  EXPECT_TRUE(WaitUntil([&] { return server.stats().active_streams == 1; }));
  EXPECT_EQ(StatusOf(Get(server.port(), "/frame.jpg")), 200);
}

TEST(MjpegServer, FrameJpgIsTheLatestFrameOr503BeforeTheFirst) {
  MjpegServer server("127.0.0.1", 0, "t");
  const std::string none = Get(server.port(), "/frame.jpg");
  EXPECT_EQ(StatusOf(none), 503) << none;
  server.PostFrame({});  // ignored
  EXPECT_EQ(StatusOf(Get(server.port(), "/frame.jpg")), 503);
  server.PostFrame(SolidJpeg(kRed));
  server.PostFrame(SolidJpeg(kBlue, 16, 16));
  const std::string response = Get(server.port(), "/frame.jpg");
  EXPECT_EQ(StatusOf(response), 200);
  EXPECT_TRUE(HasField(response, "Content-Type: image/jpeg"));
  ExpectPicture(BodyOf(response), 16, 16, kBlue);
}

TEST(MjpegServer, AnswersBadRequestsWithTheRightStatus) {
  MjpegServer server("127.0.0.1", 0, "t");
  const int port = server.port();
  EXPECT_EQ(StatusOf(Get(port, "/nothing-here")), 404);
  EXPECT_EQ(StatusOf(Get(port, "/favicon.ico")), 404);
  const std::string post = Fetch(port, "POST / HTTP/1.1\r\nContent-Length: 2\r\n\r\nhi");
  EXPECT_EQ(StatusOf(post), 405) << post;
  EXPECT_TRUE(HasField(post, "Allow: GET, HEAD")) << post;
  EXPECT_EQ(StatusOf(Fetch(port, "DELETE /stream.mjpg HTTP/1.0\r\n\r\n")), 405);
  EXPECT_EQ(StatusOf(Fetch(port, "hello there\r\n\r\n")), 400);
  EXPECT_EQ(StatusOf(Fetch(port, "\x16\x03\x01\x02\x01\r\n\r\n")), 400);  // binary
  EXPECT_EQ(StatusOf(Fetch(port, "GET / HTTP/2.0\r\n\r\n")), 400);
  EXPECT_EQ(StatusOf(Fetch(port, "GET nowhere HTTP/1.1\r\n\r\n")), 400);
  EXPECT_EQ(StatusOf(Fetch(port, "GET / HTTP/1.1\r\nno colon\r\n\r\n")), 400);
  // a head that outgrows 8 KiB
  const std::string huge = "GET / HTTP/1.1\r\nX-Big: " + std::string(9000, 'a') + "\r\n\r\n";
  EXPECT_EQ(StatusOf(Fetch(port, huge)), 431);
  // bare "\n" line ends are accepted
  EXPECT_EQ(StatusOf(Fetch(port, "GET /stats.json HTTP/1.0\n\n")), 200);
  EXPECT_EQ(server.stats().requests, 11);
}

// DNS rebinding: a page of another site, whose name now resolves here, must not read frames.
TEST(MjpegServer, AnswersOnlyToItsOwnNames) {
  MjpegServer server("127.0.0.1", 0, "t");
  const int port = server.port();
  const auto get_as = [&](const std::string& host) {
    return StatusOf(Fetch(port, "GET /stats.json HTTP/1.1\r\nHost: " + host + "\r\n\r\n"));
  };
  EXPECT_EQ(get_as("127.0.0.1:" + std::to_string(port)), 200);
  EXPECT_EQ(get_as("localhost:" + std::to_string(port)), 200);
  EXPECT_EQ(get_as("localhost"), 200);
  EXPECT_EQ(get_as("[::1]:" + std::to_string(port)), 200);
  EXPECT_EQ(get_as("evil.example:" + std::to_string(port)), 403);
  EXPECT_EQ(get_as("127.0.0.1.evil.example"), 403);
  const std::string not_found = Get(port, "/<script>");
  EXPECT_EQ(BodyOf(not_found).find("<script>"), std::string::npos);  // nothing echoed
  EXPECT_TRUE(HasField(not_found, "X-Content-Type-Options: nosniff")) << not_found;
}

TEST(MjpegServer, StatsJsonCountsWhatHappened) {
  MjpegServer server("127.0.0.1", 0, "t");
  server.PostFrame(SolidJpeg(kRed));
  Client client(server.port());
  const std::string boundary = BoundaryOf(OpenStream(&client));
  ReadPart(&client, boundary);
  const std::string response = Get(server.port(), "/stats.json");
  EXPECT_TRUE(HasField(response, "Content-Type: application/json")) << response;
  const nlohmann::json stats = nlohmann::json::parse(BodyOf(response));
  EXPECT_EQ(stats["frames_posted"], 1);
  EXPECT_GE(stats["parts_sent"].get<int>(), 1);
  EXPECT_EQ(stats["streams_opened"], 1);
  EXPECT_EQ(stats["active_streams"], 1);
  EXPECT_EQ(stats["requests"], 1);  // the stream; this request is counted once answered
  EXPECT_EQ(server.stats().requests, 2);
}

TEST(MjpegServer, StreamsBeyondTheCapAreAnswered503) {
  MjpegServer server("127.0.0.1", 0, "t");
  std::vector<std::unique_ptr<Client>> streams;
  const char* peers[] = {"127.0.0.2", "127.0.0.3", "127.0.0.4", "127.0.0.5"};  // 4 each
  static_assert(MjpegServer::kMaxStreams == 4 * MjpegServer::kMaxStreamsPerPeer);
  for (int i = 0; i < MjpegServer::kMaxStreams; ++i) {
    streams.push_back(
        std::make_unique<Client>(server.port(), peers[i / MjpegServer::kMaxStreamsPerPeer]));
    EXPECT_EQ(StatusOf(OpenStream(streams.back().get())), 200);
  }
  EXPECT_EQ(StatusOf(Get(server.port(), "/stream.mjpg")), 503);
  EXPECT_EQ(StatusOf(Get(server.port(), "/")), 200);  // other routes still answer
  EXPECT_EQ(server.stats().active_streams, MjpegServer::kMaxStreams);
}

TEST(MjpegServer, ASilentClientIsDroppedAfterTheReadTimeout) {
  MjpegServer server("127.0.0.1", 0, "t");
  Client silent(server.port());
  ASSERT_TRUE(silent.connected());
  // meanwhile others are served
  EXPECT_EQ(StatusOf(Get(server.port(), "/")), 200);
  // closed without an answer after the server's 5 s read timeout (not before: a lower bound,
  // which a loaded machine cannot break; the client's own read timeout is 10 s)
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(silent.ReadToEnd(), std::optional<std::string>(""));
  EXPECT_GE(std::chrono::steady_clock::now() - start, 4500ms);
}

TEST(MjpegServer, DestructorReturnsPromptlyWithOpenConnections) {
  auto server = std::make_unique<MjpegServer>("127.0.0.1", 0, "t");
  const int port = server->port();
  Client idle_stream(port);  // no frame yet: waits for one
  Client silent(port);       // never sends its request
  Client half(port);         // sends half a request
  ASSERT_FALSE(OpenStream(&idle_stream).empty());
  half.Send("GET / HT");
  Client stuck(port);  // a stream that stops reading, its server thread blocked in send
  ASSERT_FALSE(OpenStream(&stuck).empty());
  for (uint64_t seed = 1; seed <= 40; ++seed) server->PostFrame(NoiseJpeg(seed));
  ASSERT_TRUE(WaitUntil([&] { return server->stats().parts_sent >= 2; }));

  // a liveness check, not a speed one: waiting out a read timeout (5 s) would fail it
  const Clock::time_point start = Clock::now();
  server.reset();
  EXPECT_LT(Clock::now() - start, 3s);
  EXPECT_TRUE(silent.ReadToEnd().has_value());  // closed, not left open
}

// Slowloris and a greedy peer: one address that holds connections open with half-sent requests
// and takes every stream it can gets its share, no more, and every request of another address
// is answered. (Checked: with kMaxConnectionsPerPeer and kMaxStreamsPerPeer raised to the
// global caps, the greedy peer holds all 64 connections and this test's requests get 503.)
TEST(MjpegServer, OnePeerCannotCrowdOutTheOthers) {
  MjpegServer server("127.0.0.1", 0, "t");
  const int port = server.port();
  server.PostFrame(SolidJpeg(kRed));
  std::vector<std::unique_ptr<Client>> greedy;
  int held = 0, streams = 0;
  for (int i = 0; i < MjpegServer::kMaxStreamsPerPeer + 2; ++i) {
    greedy.push_back(std::make_unique<Client>(port, "127.0.0.2"));
    streams += StatusOf(OpenStream(greedy.back().get())) == 200;
  }
  for (int i = 0; i < MjpegServer::kMaxConnections + 6; ++i) {
    greedy.push_back(std::make_unique<Client>(port, "127.0.0.2"));
    greedy.back()->Send("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ");  // and never the rest
  }
  ASSERT_TRUE(
      WaitUntil([&] { return server.stats().refused_per_peer >= MjpegServer::kMaxConnections; }));
  for (auto& client : greedy) held += client->connected();
  EXPECT_EQ(streams, MjpegServer::kMaxStreamsPerPeer);
  EXPECT_EQ(held, static_cast<int>(greedy.size()));  // all connected; the surplus closed at once

  int answered = 0;
  for (int i = 0; i < 80; ++i)
    answered += StatusOf(Fetch(port, Request("GET", "/stats.json"))) == 200;
  EXPECT_EQ(answered, 80);
  Client viewer(port);
  EXPECT_EQ(StatusOf(OpenStream(&viewer)), 200);
}

TEST(MjpegServer, SceneAndScriptRoutes) {
  MjpegServer frames_only("127.0.0.1", 0, "t");
  EXPECT_EQ(StatusOf(Get(frames_only.port(), "/scene.json")), 404);
  MjpegServer server("127.0.0.1", 0, "t", /*expect_scene=*/true);
  EXPECT_EQ(StatusOf(Get(server.port(), "/scene.json")), 503);
  server.SetScene("{\"width\":64}");
  const std::string scene = Get(server.port(), "/scene.json");
  EXPECT_EQ(StatusOf(scene), 200);
  EXPECT_TRUE(HasField(scene, "Content-Type: application/json")) << scene;
  EXPECT_EQ(BodyOf(scene), "{\"width\":64}");
  const std::string script = Get(server.port(), "/viewer.js");
  EXPECT_EQ(StatusOf(script), 200);
  EXPECT_NE(BodyOf(script).find("getContext('webgl2'"), std::string::npos);
  // one script: the intestine's skin (viewer_tube.js) before the renderer that uses it
  const size_t tube = BodyOf(script).find("const ViewerTube = ");
  ASSERT_NE(tube, std::string::npos);
  EXPECT_LT(tube, BodyOf(script).find("const Viewer = "));
  EXPECT_EQ(StatusOf(Get(server.port(), "/skeleton")), 400);  // not an upgrade
  server.DropScene();  // the session's skeleton did not fit the scene: server frames only
  EXPECT_EQ(StatusOf(Get(server.port(), "/scene.json")), 404);
}

}  // namespace
}  // namespace viscera::client
