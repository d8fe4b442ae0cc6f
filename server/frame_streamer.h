#pragma once
/// FrameStreamer: a session's skin+render thread. At its frame rate it takes the mechanics
/// thread's latest snapshot and the session's camera, skins and draws them through its own
/// OSMesa context, encodes a JPEG and publishes it on VISCERA_FRAME_<id>. It only reads
/// what the session hands off (snapshot, camera), so a slow frame never delays a step: the
/// ticks that pass while a frame is being made are dropped and counted. It runs on the CPU
/// time nothing else in viscerad wants (SCHED_IDLE).
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "bus/lcm_bus.h"
#include "render/frame_renderer.h"
#include "session/session.h"

namespace viscera::server {

struct FrameStreamConfig {
  double rate_hz = 25.0;          ///< frames per second (> 0)
  render::FrameOptions options;   ///< size, JPEG quality, skin
};

class FrameStreamer {
 public:
  /// @pre session and bus outlive the streamer; config.rate_hz > 0.
  FrameStreamer(session::Session* session, bus::LcmBus* bus, FrameStreamConfig config);
  /// Stops the thread.
  ~FrameStreamer();
  FrameStreamer(const FrameStreamer&) = delete;
  FrameStreamer& operator=(const FrameStreamer&) = delete;

  /// Starts the thread. A renderer that cannot be made (OSMesa failure) ends the thread
  /// and says why in the session's last_error; the session runs on without frames.
  void Start();
  /// Stops the thread within one frame. Idempotent.
  void Stop();

 private:
  void Run();
  void Loop(render::FrameRenderer& renderer);

  session::Session* session_;
  bus::LcmBus* bus_;
  FrameStreamConfig config_;
  std::string channel_;
  std::thread thread_;
  std::mutex stop_mutex_;  // with stop_wake_: Stop() interrupts the wait between frames
  std::condition_variable stop_wake_;
  bool stop_ = false;
};

}  // namespace viscera::server
