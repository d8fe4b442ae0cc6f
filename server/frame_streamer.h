#pragma once
/// FrameStreamer: a session's skin+render thread. At its frame rate it takes the mechanics
/// thread's latest snapshot and the session's camera, skins and draws them through its own
/// OSMesa context (running the bowel's damaged parts, which the snapshot carries, in the damage
/// colour), encodes a JPEG and publishes it on VISCERA_FRAME_<id>. It only reads
/// what the session hands off (snapshot, camera), and never holds a lock the mechanics
/// thread waits for, so a slow frame never delays a step: the ticks that pass while a frame
/// is being made are dropped and counted. It runs on the CPU time nothing else in viscerad
/// wants (SCHED_IDLE).
#include <atomic>
#include <string>

#include "bus/lcm_bus.h"
#include "common/stoppable_thread.h"
#include "render/frame_renderer.h"
#include "session/session.h"

namespace viscera::server {

struct FrameStreamConfig {
  double rate_hz = 25.0;  ///< frames per second (>= kMinFrameRateHz)
  /// Frames are drawn only while the session's frame lease (Session::WatchFrames) was renewed
  /// within this long (s); 0: always.
  double lease_s = 0.0;
  /// Lower the rate, then the size, under load and climb back when calm (FrameGovernor);
  /// false: the configured rate and size, always.
  bool adaptive = true;
  render::FrameOptions options;  ///< size, JPEG quality, skin
};

class FrameStreamer {
 public:
  /// @pre session and bus outlive the streamer; config.rate_hz >= kMinFrameRateHz.
  FrameStreamer(session::Session* session, bus::LcmBus* bus, FrameStreamConfig config);
  /// Stops the thread (Stop).
  ~FrameStreamer();
  FrameStreamer(const FrameStreamer&) = delete;
  FrameStreamer& operator=(const FrameStreamer&) = delete;

  /// Starts the thread. A renderer that cannot be made (OSMesa failure) ends the thread
  /// and says why in the session's last_error; the session runs on without frames.
  void Start();
  /// Asks the thread to stop after the frame it is making; returns at once.
  void RequestStop();
  /// True once the thread has ended (after RequestStop, or a renderer that failed).
  bool finished() const { return finished_.load(); }
  /// RequestStop, then waits for the thread. Idempotent.
  void Stop();

 private:
  void Run();
  void Loop(render::FrameRenderer& renderer, session::FrameStreamReport* report);
  void ReportError(session::FrameStreamReport* report, const std::string& why);

  session::Session* session_;
  bus::LcmBus* bus_;
  FrameStreamConfig config_;
  std::string channel_;
  StoppableThread worker_;
  std::atomic<bool> finished_{false};
};

}  // namespace viscera::server
