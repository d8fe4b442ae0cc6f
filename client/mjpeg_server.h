#pragma once
/// MjpegServer: serves the latest JPEG frames over HTTP for `viscera view ID --http HOST:PORT`,
/// to any browser (an <img> on a small page) or tool, with POSIX sockets and one thread per
/// connection. Routes (GET or HEAD; other methods 405, unknown paths 404, bad requests 400):
///   /             the viewer page (client/mjpeg_page.h)
///   /stream.mjpg  multipart/x-mixed-replace, one image/jpeg part per new frame (starting
///                 with the latest at once); a frame that no newer one follows within 0.1 s
///                 is sent once more, because Chromium shows a part only when the next begins
///   /frame.jpg    the latest frame once (503 before the first)
///   /stats.json   MjpegServerStats as JSON
/// A client gets 5 s to send its request (8 KiB at most, else 431); a stream client that
/// takes no bytes for 10 s is dropped.
#include <condition_variable>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace viscera::client {

struct MjpegServerStats {
  int64_t frames_posted = 0;   ///< PostFrame calls
  int64_t parts_sent = 0;      ///< JPEG parts written to all stream clients
  int64_t streams_opened = 0;  ///< /stream.mjpg connections accepted since start
  int active_streams = 0;      ///< open now
  int64_t requests = 0;        ///< HTTP requests answered (all paths, incl. errors)
};

/// The stats as a JSON object, keys in the order of the struct.
std::string StatsToJson(const MjpegServerStats& stats);

/// Parses "HOST:PORT": HOST an IPv4 dotted quad or "localhost", PORT in 0..65535.
/// @throws InputError naming the text and what is wrong with it.
void ParseHostPort(const std::string& text, std::string* host, int* port);

class MjpegServer {
 public:
  /// Most /stream.mjpg clients at once; the next is answered 503.
  static constexpr int kMaxStreams = 16;
  /// Most connections at once (streams included); the next is answered 503 and closed.
  static constexpr int kMaxConnections = 64;

  /// Binds host:port (host as ParseHostPort accepts; port 0 = an ephemeral port, see
  /// port()) and starts serving. `title` names the viewer page.
  /// @throws InputError when the address is bad or cannot be bound (with the errno text).
  MjpegServer(const std::string& host, int port, std::string title);
  /// Stops accepting, closes every connection and joins every thread (promptly: blocked
  /// reads and writes are woken by shutting their sockets down).
  ~MjpegServer();
  MjpegServer(const MjpegServer&) = delete;
  MjpegServer& operator=(const MjpegServer&) = delete;

  /// The port bound (the ephemeral one when constructed with port 0).
  int port() const { return port_; }

  /// Makes `jpeg` the latest frame. Any thread; never blocks on a client: each stream sends
  /// the newest frame when it is ready for one, so a slow browser skips frames.
  /// An empty `jpeg` is ignored (and not counted).
  void PostFrame(std::vector<uint8_t> jpeg);

  MjpegServerStats stats() const;

 private:
  using Frame = std::shared_ptr<const std::vector<uint8_t>>;
  struct Connection {
    int fd = -1;  ///< -1 once the connection's thread has closed it
    std::thread thread;
    bool done = false;
  };

  void AcceptLoop();
  // One connection's thread: reads one request, answers it, closes.
  void Serve(Connection* connection);
  void Answer(int fd, const std::string& head);
  void Stream(int fd, bool head_only);
  // Sends a whole response (or only its head) and counts it.
  bool Respond(int fd, int status, std::string_view content_type, std::string_view body,
               bool head_only, std::string_view extra_fields = "");
  // Joins the threads of finished connections, or of all of them.
  void Reap(bool all);

  const std::string page_;
  int listen_fd_ = -1;
  int wake_pipe_[2] = {-1, -1};  // written once by the destructor, to wake AcceptLoop's poll
  int port_ = 0;
  std::string ip_;  // the address bound, dotted quad: a Host header may name it

  mutable std::mutex mutex_;  // guards everything below
  std::condition_variable frame_posted_;
  Frame frame_;                // the latest; its sequence number is stats_.frames_posted
  MjpegServerStats stats_;
  bool stopping_ = false;
  std::list<Connection> connections_;  // a list: Serve holds a pointer to its element

  std::thread accept_thread_;  // last: started once everything above is ready
};

}  // namespace viscera::client
