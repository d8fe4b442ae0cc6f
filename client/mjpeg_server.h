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
///   /viewer.js    the page's WebGL renderer (client/web/viewer_tube.js and viewer.js)
///   /scene.json   what the page draws the session from (SetScene; 404 when there is none,
///                 503 until it is set)
///   /skeleton     a WebSocket (Boost.Beast) of skeleton messages (PostSkeleton), the latest
///                 at once, then each new one; a slow page skips messages
/// A client gets 5 s to send its whole request head (8 KiB at most, else 431); a stream client
/// that takes no bytes for 10 s is dropped. One peer address holds at most
/// kMaxConnectionsPerPeer connections and kMaxStreamsPerPeer streams (MJPEG and WebSocket
/// each): a slow or greedy peer cannot crowd out the others.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace viscera::client {

struct MjpegServerStats {
  int64_t frames_posted = 0;     ///< PostFrame calls
  int64_t parts_sent = 0;        ///< JPEG parts written to all stream clients
  int64_t streams_opened = 0;    ///< /stream.mjpg connections accepted since start
  int active_streams = 0;        ///< open now
  int64_t requests = 0;          ///< HTTP requests answered (all paths, incl. errors)
  int64_t skeletons_posted = 0;  ///< PostSkeleton calls
  int64_t messages_sent = 0;     ///< skeleton messages written to all WebSockets
  int active_sockets = 0;        ///< /skeleton WebSockets open now
  int64_t refused_per_peer = 0;  ///< connections and streams refused by the per-peer limits
  int64_t frame_requests = 0;    ///< /frame.jpg requests
  /// The latest frame as the viewer received it (NoteFrame): its step, its age when it
  /// arrived (ms: arrival - snapshot time), ms since it arrived (-1: none yet), and the rate of
  /// frames over about the last 2 s (Hz).
  int64_t frame_step = -1;
  double frame_age_ms = 0.0;
  double since_frame_ms = -1.0;
  double frame_rate_hz = 0.0;
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
  /// Most connections at once from one peer address; the next is answered 503 and closed.
  static constexpr int kMaxConnectionsPerPeer = 8;
  /// Most /stream.mjpg streams, and most /skeleton sockets, of one peer address at once.
  static constexpr int kMaxStreamsPerPeer = 4;
  /// Most /skeleton WebSockets at once.
  static constexpr int kMaxSockets = 16;

  /// Binds host:port (host as ParseHostPort accepts; port 0 = an ephemeral port, see
  /// port()) and starts serving. `title` names the viewer page.
  /// @throws InputError when the address is bad or cannot be bound (with the errno text).
  /// `expect_scene`: the page may draw the session itself (a scene will be set).
  MjpegServer(const std::string& host, int port, std::string title, bool expect_scene = false);
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

  /// Notes the step and age (ms) of the frame just posted, for /stats.json (the page shows them).
  void NoteFrame(int64_t step, double age_ms);

  /// The page's scene (client/view_scene.h); until it is set /scene.json answers 503, and
  /// without ever calling it (`expect_scene` false at construction) 404.
  void SetScene(std::string json);
  /// No scene after all (the session's skeleton does not fit the scene file): /scene.json
  /// answers 404 from now on, and the page shows server frames.
  void DropScene();

  /// Makes `json` the latest skeleton message; any thread, never blocks on a page.
  void PostSkeleton(std::string json);

 private:
  using Frame = std::shared_ptr<const std::vector<uint8_t>>;
  using Text = std::shared_ptr<const std::string>;
  struct Connection {
    int fd = -1;        ///< -1 once the connection's thread has closed it
    uint32_t peer = 0;  ///< the peer's IPv4 address (network order)
    std::thread thread;
    bool done = false;
  };

  void AcceptLoop();
  // One connection's thread: reads one request, answers it, closes.
  void Serve(Connection* connection);
  void Answer(int fd, const std::string& head, uint32_t peer);
  void Stream(int fd, bool head_only, uint32_t peer);
  void Socket(int fd, const std::string& head, uint32_t peer);
  // Takes a stream slot of `kind` (MJPEG or WebSocket) for `peer`, or says why not.
  std::string AdmitStream(bool socket, uint32_t peer);
  // Sends a whole response (or only its head) and counts it.
  bool Respond(int fd, int status, std::string_view content_type, std::string_view body,
               bool head_only, std::string_view extra_fields = "");
  // Joins the threads of finished connections, or of all of them.
  void Reap(bool all);

  const std::string page_;
  bool expect_scene_;  // guarded by mutex_
  int listen_fd_ = -1;
  int wake_pipe_[2] = {-1, -1};  // written once by the destructor, to wake AcceptLoop's poll
  int port_ = 0;
  std::string ip_;  // the address bound, dotted quad: a Host header may name it

  mutable std::mutex mutex_;  // guards everything below
  std::condition_variable frame_posted_;
  Frame frame_;            // the latest; its sequence number is stats_.frames_posted
  Text scene_, skeleton_;  // the page's scene; the latest skeleton (number: skeletons_posted)
  MjpegServerStats stats_;
  std::chrono::steady_clock::time_point frame_arrived_;
  std::vector<std::chrono::steady_clock::time_point> frame_times_;  // arrivals of the last 2 s
  std::map<uint32_t, int> peer_streams_, peer_sockets_;             // open per peer
  bool stopping_ = false;
  std::list<Connection> connections_;  // a list: Serve holds a pointer to its element

  std::thread accept_thread_;  // last: started once everything above is ready
};

}  // namespace viscera::client
