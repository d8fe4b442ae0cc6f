#pragma once
/// ExposureWatcher: a session's target-exposure thread (docs/assessment.md). At the scene's
/// [assessment] exposure_rate it takes the mechanics thread's latest snapshot and the camera
/// the frames are drawn from (session_view.h), places the sphere chain on it and casts a ray to
/// every sample of every target; the session keeps the results for its status and report, and
/// the camera for running the bowel's camera coverage (Session::ReportView). It
/// only reads what the session hands off, off the mechanics thread, at nice 10 (a few hundred
/// microseconds per evaluation: it is never starved, and never delays a step).
#include <atomic>
#include <cstdint>

#include "common/stoppable_thread.h"
#include "session/session.h"

namespace viscera::server {

struct ExposureWatchConfig {
  int width = 640, height = 480;  ///< the frame the camera frames the scene for (pixels)
};

class ExposureWatcher {
 public:
  /// @pre session outlives the watcher; its scene has targets or [running].
  ExposureWatcher(session::Session* session, ExposureWatchConfig config);
  ~ExposureWatcher();
  ExposureWatcher(const ExposureWatcher&) = delete;
  ExposureWatcher& operator=(const ExposureWatcher&) = delete;

  void Start();
  /// Asks the thread to stop after the evaluation it is making; returns at once.
  void RequestStop();
  bool finished() const { return finished_.load(); }
  /// RequestStop, then waits for the thread. Idempotent.
  void Stop();
  /// Evaluations made so far (each covers every target).
  int64_t evaluations() const { return evaluations_.load(); }

 private:
  void Run();

  session::Session* session_;
  ExposureWatchConfig config_;
  StoppableThread worker_;
  std::atomic<bool> finished_{false};
  std::atomic<int64_t> evaluations_{0};
};

}  // namespace viscera::server
