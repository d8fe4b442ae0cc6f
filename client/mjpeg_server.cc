#include "client/mjpeg_server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <strings.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <system_error>

#include "client/http_request.h"
#include "client/mjpeg_page.h"
#include "client/skeleton_socket.h"
#include "client/viewer_script.h"
#include "common/check.h"

namespace viscera::client {
namespace {

// The host of a Host field: "host:port" or "host", "[v6]:port" or "[v6]".
std::string HostOfHostField(const std::string& value) {
  const size_t colon = value.rfind(':'), bracket = value.rfind(']');
  const bool has_port =
      colon != std::string::npos && (bracket == std::string::npos || colon > bracket);
  return has_port ? value.substr(0, colon) : value;
}

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr const char* kBoundary = "visceraframe";
// A client gets this long to send its request: silent connections (Chromium opens
// speculative ones) must not hold a thread forever.
constexpr auto kReadTimeout = 5s;
// A stream client that takes no bytes for this long is gone or frozen: its slot is freed.
constexpr timeval kSendTimeout = {10, 0};
// Chromium shows a part only when the next part's headers arrive (blink's multipart parser
// ignores Content-Length), so a frame that no newer one follows within this time is sent
// once more, which puts it on screen.
constexpr auto kRepeatAfter = 100ms;
// How often an idle stream (no new frames) checks that its client is still there.
constexpr auto kIdleCheck = 1s;
// How long a finished connection waits for the client to close first (see Linger).
constexpr int kLingerMs = 1000;

std::string ErrnoText(int error) { return std::generic_category().message(error); }

const char* Reason(int status) {
  switch (status) {
    case 200: return "OK";
    case 400: return "Bad Request";
    case 403: return "Forbidden";
    case 404: return "Not Found";
    case 405: return "Method Not Allowed";
    case 431: return "Request Header Fields Too Large";
    case 503: return "Service Unavailable";
  }
  return "Error";
}

// MSG_NOSIGNAL: a vanished client gives EPIPE, never a SIGPIPE that kills the viewer.
bool SendAll(int fd, std::string_view data, int flags = 0) {
  while (!data.empty()) {
    const ssize_t n = send(fd, data.data(), data.size(), flags | MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;  // EPIPE, ECONNRESET, or EAGAIN after kSendTimeout
    data.remove_prefix(static_cast<size_t>(n));
  }
  return true;
}

std::string_view Bytes(const std::vector<uint8_t>& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

enum class HeadRead { kComplete, kTooLarge, kGone };

// Reads until the blank line that ends a request head, within kReadTimeout; on kComplete
// `data` holds the head, and only the head.
HeadRead ReadHead(int fd, std::string* data) {
  const Clock::time_point deadline = Clock::now() + kReadTimeout;
  char buffer[2048];
  while (true) {
    const size_t end = FindHeadEnd(*data);
    if (end > kMaxRequestHead || (end == 0 && data->size() >= kMaxRequestHead)) {
      return HeadRead::kTooLarge;
    }
    if (end > 0) {
      data->resize(end);
      return HeadRead::kComplete;
    }
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) return HeadRead::kGone;
    pollfd readable{fd, POLLIN, 0};
    const int ready = poll(&readable, 1, static_cast<int>(left.count()));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) return HeadRead::kGone;
    const ssize_t n = recv(fd, buffer, sizeof(buffer), 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return HeadRead::kGone;
    data->append(buffer, static_cast<size_t>(n));
  }
}

// Ends our side politely: closing with unread input resets the connection, and a reset
// can destroy the response before the client has read it. So shut down sending, then
// drain until the client closes (or kLingerMs pass).
void Linger(int fd) {
  shutdown(fd, SHUT_WR);
  const Clock::time_point deadline = Clock::now() + std::chrono::milliseconds(kLingerMs);
  char buffer[2048];
  while (true) {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) return;
    pollfd readable{fd, POLLIN, 0};
    if (poll(&readable, 1, static_cast<int>(left.count())) <= 0) return;
    if (recv(fd, buffer, sizeof(buffer), 0) <= 0) return;
  }
}

// True when the client closed (or reset) its side: a stream client never sends after its
// request, so this is a browser that left.
bool PeerClosed(int fd) {
  pollfd state{fd, POLLRDHUP, 0};
  return poll(&state, 1, 0) > 0 && (state.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0;
}

bool SendPart(int fd, const std::vector<uint8_t>& jpeg) {
  const std::string head = Cat(
      "--", kBoundary, "\r\nContent-Type: image/jpeg\r\nContent-Length: ", jpeg.size(), "\r\n\r\n");
  // MSG_MORE: one part, as few segments as possible; the last send pushes it out
  return SendAll(fd, head, MSG_MORE) && SendAll(fd, Bytes(jpeg), MSG_MORE) && SendAll(fd, "\r\n");
}

}  // namespace

std::string StatsToJson(const MjpegServerStats& stats) {
  return Cat(
      "{\"frames_posted\":", stats.frames_posted, ",\"parts_sent\":", stats.parts_sent,
      ",\"streams_opened\":", stats.streams_opened, ",\"active_streams\":", stats.active_streams,
      ",\"requests\":", stats.requests, ",\"skeletons_posted\":", stats.skeletons_posted,
      ",\"messages_sent\":", stats.messages_sent, ",\"active_sockets\":", stats.active_sockets,
      ",\"refused_per_peer\":", stats.refused_per_peer,
      ",\"frame_requests\":", stats.frame_requests, ",\"frame_step\":", stats.frame_step,
      ",\"frame_age_ms\":", stats.frame_age_ms, ",\"since_frame_ms\":", stats.since_frame_ms,
      ",\"frame_rate_hz\":", stats.frame_rate_hz, "}\n");
}

void ParseHostPort(const std::string& text, std::string* host, int* port) {
  VISCERA_DEMAND(host != nullptr && port != nullptr);
  const size_t colon = text.rfind(':');
  ThrowUnless(colon != std::string::npos, "address '", text, "' is not HOST:PORT");
  const std::string host_text = text.substr(0, colon);
  const std::string port_text = text.substr(colon + 1);
  in_addr ignored{};
  ThrowUnless(host_text == "localhost" || inet_pton(AF_INET, host_text.c_str(), &ignored) == 1,
              "address '", text, "': host '", host_text,
              "' is neither an IPv4 dotted quad nor localhost");
  bool digits = !port_text.empty() && port_text.size() <= 5;
  for (char c : port_text) digits = digits && c >= '0' && c <= '9';
  ThrowUnless(digits && std::stoi(port_text) <= 65535, "address '", text, "': port '", port_text,
              "' is not a number in 0..65535");
  *host = host_text;
  *port = std::stoi(port_text);
}

MjpegServer::MjpegServer(const std::string& host, int port, std::string title, bool expect_scene)
    : page_(MjpegPage(title)), expect_scene_(expect_scene) {
  ThrowUnless(port >= 0 && port <= 65535, "MJPEG server: port ", port, " is not in 0..65535");
  in_addr address{};
  const std::string ip = host == "localhost" ? "127.0.0.1" : host;
  ThrowUnless(inet_pton(AF_INET, ip.c_str(), &address) == 1, "MJPEG server: host '", host,
              "' is neither an IPv4 dotted quad nor localhost");

  // the constructor throws before the destructor could close anything: close here
  const auto fail = [this](auto&&... message) {
    const int error = errno;
    for (int fd : {listen_fd_, wake_pipe_[0], wake_pipe_[1]}) {
      if (fd >= 0) close(fd);
    }
    Fail("MJPEG server: ", message..., ": ", ErrnoText(error));
  };
  listen_fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) fail("socket");
  // a restarted viewer can bind again while its old connections sit in TIME_WAIT
  const int one = 1;
  setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  sockaddr_in bound{};
  bound.sin_family = AF_INET;
  bound.sin_port = htons(static_cast<uint16_t>(port));
  bound.sin_addr = address;
  if (bind(listen_fd_, reinterpret_cast<sockaddr*>(&bound), sizeof(bound)) != 0) {
    fail("cannot bind ", host, ":", port);
  }
  if (listen(listen_fd_, 16) != 0) fail("cannot listen on ", host, ":", port);
  socklen_t length = sizeof(bound);
  if (getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&bound), &length) != 0) {
    fail("getsockname");
  }
  port_ = ntohs(bound.sin_port);
  ip_ = ip;
  if (pipe2(wake_pipe_, O_CLOEXEC) != 0) fail("pipe");
  try {
    accept_thread_ = std::thread(&MjpegServer::AcceptLoop, this);
  } catch (const std::system_error& e) {
    errno = e.code().value();
    fail("cannot start a thread");
  }
}

MjpegServer::~MjpegServer() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    // wakes every blocked poll, recv and send of the connections' threads
    for (Connection& connection : connections_) {
      if (connection.fd >= 0) shutdown(connection.fd, SHUT_RDWR);
    }
  }
  frame_posted_.notify_all();
  const char wake = 1;
  while (write(wake_pipe_[1], &wake, 1) < 0 && errno == EINTR) {
  }
  accept_thread_.join();
  Reap(/*all=*/true);
  close(listen_fd_);
  close(wake_pipe_[0]);
  close(wake_pipe_[1]);
}

void MjpegServer::PostFrame(std::vector<uint8_t> jpeg) {
  if (jpeg.empty()) return;
  Frame frame = std::make_shared<const std::vector<uint8_t>>(std::move(jpeg));
  {
    std::lock_guard lock(mutex_);
    frame_.swap(frame);
    ++stats_.frames_posted;
  }
  frame_posted_.notify_all();
  // `frame` now holds the previous one, freed here (outside the lock) unless a stream sends it
}

MjpegServerStats MjpegServer::stats() const {
  std::lock_guard lock(mutex_);
  MjpegServerStats s = stats_;
  if (s.frame_step >= 0) {
    const auto now = Clock::now();
    s.since_frame_ms = std::chrono::duration<double, std::milli>(now - frame_arrived_).count();
    const auto recent = std::count_if(frame_times_.begin(), frame_times_.end(),
                                      [&](Clock::time_point t) { return now - t <= 2s; });
    s.frame_rate_hz = static_cast<double>(recent) / 2.0;
  }
  return s;
}

void MjpegServer::NoteFrame(int64_t step, double age_ms) {
  const auto now = Clock::now();
  std::lock_guard lock(mutex_);
  stats_.frame_step = step;
  stats_.frame_age_ms = age_ms;
  frame_arrived_ = now;
  std::erase_if(frame_times_, [&](Clock::time_point t) { return now - t > 2s; });
  frame_times_.push_back(now);
}

void MjpegServer::SetScene(std::string json) {
  Text scene = std::make_shared<const std::string>(std::move(json));
  std::lock_guard lock(mutex_);
  scene_.swap(scene);
}

void MjpegServer::DropScene() {
  std::lock_guard lock(mutex_);
  scene_.reset();
  expect_scene_ = false;
}

void MjpegServer::PostSkeleton(std::string json) {
  Text skeleton = std::make_shared<const std::string>(std::move(json));
  {
    std::lock_guard lock(mutex_);
    skeleton_.swap(skeleton);
    ++stats_.skeletons_posted;
  }
  frame_posted_.notify_all();
}

void MjpegServer::AcceptLoop() {
  while (true) {
    pollfd ready[2] = {{listen_fd_, POLLIN, 0}, {wake_pipe_[0], POLLIN, 0}};
    if (poll(ready, 2, -1) < 0) continue;  // EINTR; nothing else can fail here
    if (ready[1].revents != 0) return;
    if ((ready[0].revents & POLLIN) == 0) continue;
    sockaddr_in peer{};
    socklen_t peer_length = sizeof(peer);
    const int fd =
        accept4(listen_fd_, reinterpret_cast<sockaddr*>(&peer), &peer_length, SOCK_CLOEXEC);
    if (fd < 0) {
      // out of descriptors (EMFILE) keeps the listener readable: do not spin
      if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
        std::this_thread::sleep_for(10ms);
      }
      continue;
    }
    Reap(/*all=*/false);
    std::lock_guard lock(mutex_);
    if (stopping_) {
      close(fd);
      return;
    }
    const auto from_peer = std::count_if(
        connections_.begin(), connections_.end(),
        [&](const Connection& c) { return !c.done && c.peer == peer.sin_addr.s_addr; });
    if (from_peer >= kMaxConnectionsPerPeer) ++stats_.refused_per_peer;
    if (connections_.size() >= static_cast<size_t>(kMaxConnections) ||
        from_peer >= kMaxConnectionsPerPeer) {
      // answered here without blocking: a fresh socket's buffer takes a short reply
      static constexpr std::string_view kBusy =
          "HTTP/1.0 503 Service Unavailable\r\nContent-Length: 0\r\nConnection: close\r\n\r\n";
      send(fd, kBusy.data(), kBusy.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      ++stats_.requests;
      close(fd);
      continue;
    }
    Connection& connection = connections_.emplace_back();
    connection.fd = fd;
    connection.peer = peer.sin_addr.s_addr;
    try {
      connection.thread = std::thread(&MjpegServer::Serve, this, &connection);
    } catch (const std::system_error&) {  // no thread to be had: drop this client
      close(fd);
      connections_.pop_back();
    }
  }
}

void MjpegServer::Reap(bool all) {
  std::list<Connection> finished;
  {
    std::lock_guard lock(mutex_);
    for (auto it = connections_.begin(); it != connections_.end();) {
      // splice keeps the element where it is, so a running Serve's pointer stays valid
      const auto next = std::next(it);
      if (all || it->done) finished.splice(finished.end(), connections_, it);
      it = next;
    }
  }
  for (Connection& connection : finished) connection.thread.join();
}

void MjpegServer::Serve(Connection* connection) {
  const int fd = connection->fd;  // set before this thread started; only this thread closes it
  const int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &kSendTimeout, sizeof(kSendTimeout));

  std::string head;
  switch (ReadHead(fd, &head)) {
    case HeadRead::kComplete: Answer(fd, head, connection->peer); break;
    case HeadRead::kTooLarge:
      Respond(fd, 431, "text/plain", "request head larger than 8 KiB\n", false);
      break;
    case HeadRead::kGone:  // left, or silent past kReadTimeout: nobody to answer
      break;
  }
  Linger(fd);

  std::lock_guard lock(mutex_);
  close(fd);
  connection->fd = -1;
  connection->done = true;
}

void MjpegServer::Answer(int fd, const std::string& head, uint32_t peer) {
  HttpRequest request;
  const std::string problem = ParseHttpRequest(head, &request);
  if (!problem.empty()) {
    Respond(fd, 400, "text/plain", Cat("bad request: ", problem, "\n"), false);
    return;
  }
  // A page elsewhere could make a browser ask us for frames under a hostname of its own that
  // resolves here (DNS rebinding): only our own names are served.
  for (const auto& [name, value] : request.fields) {
    if (strcasecmp(name.c_str(), "Host") != 0) continue;
    const std::string host = HostOfHostField(value);
    if (host != "127.0.0.1" && host != "localhost" && host != "[::1]" && host != ip_) {
      Respond(fd, 403, "text/plain", "this viewer answers only to its own address\n", false);
      return;
    }
  }
  const bool head_only = request.method == "HEAD";
  if (request.method != "GET" && !head_only) {
    Respond(fd, 405, "text/plain", Cat("method ", request.method, " not allowed\n"), false,
            "Allow: GET, HEAD\r\n");
    return;
  }

  if (request.path == "/" || request.path == "/index.html") {
    Respond(fd, 200, "text/html; charset=utf-8", page_, head_only);
  } else if (request.path == "/stream.mjpg") {
    Stream(fd, head_only, peer);
  } else if (request.path == "/viewer.js") {
    Respond(fd, 200, "text/javascript; charset=utf-8", kViewerScript, head_only);
  } else if (request.path == "/scene.json") {
    Text scene;
    bool expected = false;
    {
      std::lock_guard lock(mutex_);
      scene = scene_;
      expected = expect_scene_;
    }
    if (scene != nullptr) {
      Respond(fd, 200, "application/json", *scene, head_only);
    } else if (expected) {
      Respond(fd, 503, "text/plain", "no skeleton of the session yet\n", head_only,
              "Retry-After: 1\r\n");
    } else {
      Respond(fd, 404, "text/plain", "this viewer has no scene: server frames only\n", head_only);
    }
  } else if (request.path == "/skeleton" && !head_only) {
    // a page elsewhere may open a WebSocket to any address: only our own page's origin
    for (const auto& [name, value] : request.fields) {
      if (strcasecmp(name.c_str(), "Origin") != 0) continue;
      const size_t scheme = value.find("://");
      const std::string host =
          HostOfHostField(scheme == std::string::npos ? value : value.substr(scheme + 3));
      if (host != "127.0.0.1" && host != "localhost" && host != "[::1]" && host != ip_) {
        Respond(fd, 403, "text/plain", "the skeleton stream is for this viewer's own page\n",
                false);
        return;
      }
    }
    if (!IsWebSocketUpgrade(head)) {
      Respond(fd, 400, "text/plain", "/skeleton is a WebSocket\n", false);
      return;
    }
    Socket(fd, head, peer);
  } else if (request.path == "/frame.jpg") {
    Frame frame;
    {
      std::lock_guard lock(mutex_);
      frame = frame_;
      ++stats_.frame_requests;
    }
    if (frame == nullptr) {
      Respond(fd, 503, "text/plain", "no frame yet\n", head_only, "Retry-After: 1\r\n");
    } else {
      Respond(fd, 200, "image/jpeg", Bytes(*frame), head_only);
    }
  } else if (request.path == "/stats.json") {
    Respond(fd, 200, "application/json", StatsToJson(stats()), head_only);
  } else {
    Respond(fd, 404, "text/plain", "not found: try / or /stream.mjpg\n", head_only);
  }
}

bool MjpegServer::Respond(int fd, int status, std::string_view content_type, std::string_view body,
                          bool head_only, std::string_view extra_fields) {
  {
    std::lock_guard lock(mutex_);
    ++stats_.requests;
  }
  const std::string head =
      Cat("HTTP/1.0 ", status, " ", Reason(status), "\r\nContent-Type: ", content_type,
          "\r\nContent-Length: ", body.size(),
          "\r\nCache-Control: no-cache\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n",
          extra_fields, "\r\n");
  if (head_only || body.empty()) return SendAll(fd, head);
  return SendAll(fd, head, MSG_MORE) && SendAll(fd, body);
}

std::string MjpegServer::AdmitStream(bool socket, uint32_t peer) {
  std::lock_guard lock(mutex_);
  int& open = socket ? stats_.active_sockets : stats_.active_streams;
  int& mine = (socket ? peer_sockets_ : peer_streams_)[peer];
  const int most = socket ? kMaxSockets : kMaxStreams;
  if (open >= most) return Cat("already ", most, socket ? " sockets" : " streams", " open\n");
  if (mine >= kMaxStreamsPerPeer) {
    ++stats_.refused_per_peer;
    return Cat("already ", kMaxStreamsPerPeer, socket ? " sockets" : " streams",
               " open from your address\n");
  }
  ++open;
  ++mine;
  return "";
}

void MjpegServer::Socket(int fd, const std::string& head, uint32_t peer) {
  const std::string refused = AdmitStream(/*socket=*/true, peer);
  if (!refused.empty()) {
    Respond(fd, 503, "text/plain", refused, false, "Retry-After: 1\r\n");
    return;
  }
  {
    std::lock_guard lock(mutex_);
    ++stats_.requests;
  }
  int64_t sent_number = 0;
  // the latest message at once, then each new one; every second a look whether the page left
  ServeWebSocket(fd, head, [&]() -> std::optional<std::string> {
    std::unique_lock lock(mutex_);
    while (!stopping_ && (skeleton_ == nullptr || stats_.skeletons_posted == sent_number)) {
      frame_posted_.wait_for(lock, kIdleCheck);
      if (stopping_) break;
      if (skeleton_ == nullptr || stats_.skeletons_posted == sent_number) {
        lock.unlock();
        const bool left = PeerSpokeOrLeft(fd);
        lock.lock();
        if (left) return std::nullopt;
      }
    }
    if (stopping_) return std::nullopt;
    if (sent_number != 0) ++stats_.messages_sent;  // the one before went out
    sent_number = stats_.skeletons_posted;
    return *skeleton_;
  });
  std::lock_guard lock(mutex_);
  --stats_.active_sockets;
  --peer_sockets_[peer];
}

void MjpegServer::Stream(int fd, bool head_only, uint32_t peer) {
  if (!head_only) {
    const std::string refused = AdmitStream(/*socket=*/false, peer);
    if (!refused.empty()) {
      Respond(fd, 503, "text/plain", refused, false, "Retry-After: 1\r\n");
      return;
    }
  }
  {
    std::lock_guard lock(mutex_);
    ++stats_.requests;
    if (!head_only) ++stats_.streams_opened;
  }
  const bool ok = SendAll(fd, Cat("HTTP/1.0 200 OK\r\nContent-Type: multipart/x-mixed-replace; "
                                  "boundary=",
                                  kBoundary,
                                  "\r\nCache-Control: no-cache\r\n"
                                  "X-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n"));
  if (head_only) return;

  Frame sent;               // the frame of the last part
  int64_t sent_number = 0;  // its number (frames_posted when it was posted); 0: none yet
  bool repeat_due = false;  // no newer frame followed `sent` yet
  std::unique_lock lock(mutex_);
  while (ok) {
    const auto newer = [&] { return stopping_ || stats_.frames_posted != sent_number; };
    if (frame_posted_.wait_for(lock, repeat_due ? kRepeatAfter : kIdleCheck, newer)) {
      if (stopping_) break;
      // the latest wins: frames posted while this client was busy are never sent
      sent = frame_;
      sent_number = stats_.frames_posted;
      repeat_due = true;
    } else if (repeat_due) {
      repeat_due = false;  // `sent` once more (kRepeatAfter)
    } else {
      lock.unlock();
      const bool closed = PeerClosed(fd);
      lock.lock();
      if (closed) break;
      continue;
    }
    lock.unlock();
    const bool part_sent = SendPart(fd, *sent);
    lock.lock();
    if (!part_sent) break;  // the client left (EPIPE, ECONNRESET) or stopped reading
    ++stats_.parts_sent;
  }
  --stats_.active_streams;
  --peer_streams_[peer];
}

}  // namespace viscera::client
