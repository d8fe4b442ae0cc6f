#pragma once
/// StatusBoard: what a session says of itself, and who may write what. The mechanics thread
/// posts its figures and state; any thread counts rejected messages and keeps the last
/// error; the render thread reports its frame stream. Two locks: `status_mutex_` guards the
/// posted status and the last error; the render thread's report has a lock of its own that
/// readers only try: the render thread runs at idle priority, and preempted while holding a
/// lock it could hold it for a long time, so no one ever waits for it.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#include <viscera_proto/session_status_t.hpp>

namespace viscera::session {

/// What a session's render thread reports of its frame stream; merged into every status.
struct FrameStreamReport {
  std::string error;         ///< the render thread's last problem ("" if none)
  int64_t error_serial = 0;  ///< +1 per new error: Status() takes each one once
  std::string skin;
  int width = 0, height = 0;      ///< pixels
  double rate_hz = 0.0;           ///< aimed at now (Hz): the configured rate, lowered under load
  double achieved_rate_hz = 0.0;  ///< over about the last second (Hz)
  int64_t frames = 0;             ///< sent
  int64_t dropped = 0;            ///< skipped: the renderer was busy
  float skin_ms = 0, render_ms = 0, encode_ms = 0;  ///< medians over about the last second
  int32_t frame_bytes = 0;                          ///< JPEG size of the last frame rendered
};

class StatusBoard {
 public:
  /// @param first the status read until the mechanics thread posts one.
  explicit StatusBoard(const viscera_proto::session_status_t& first) : status_(first) {}

  /// Counts a message dropped as invalid (any thread), keeping `why` as the last error.
  void CountRejected(const std::string& why);
  /// Counts a replayed or stale message (also a rejected one).
  void CountReplayed(const std::string& why);
  /// Counts an accepted pose.
  void CountPose() { ++poses_; }
  /// Keeps `why` as the last error, counting nothing. Any thread.
  void SetError(const std::string& why);
  /// The render thread's latest figures and problems.
  void ReportFrames(const FrameStreamReport& report);
  /// The mechanics' step slack over the last status period (StepSlack: 1 - the 90th percentile
  /// step wall time / step period; 1 before any). Lock-free both ways: the render thread reads
  /// it every frame.
  void SetStepSlack(double slack) { step_slack_.store(slack, std::memory_order_relaxed); }
  double step_slack() const { return step_slack_.load(std::memory_order_relaxed); }

  /// The status last posted, with the counters, the last error and the latest frame figures
  /// the render thread's lock let through. Any thread.
  viscera_proto::session_status_t Read() const;
  /// Makes `*status` the one Read() starts from; `new_state` (>= 0) becomes the state (also
  /// of `*status`) in the same critical section, so no reader sees the new state with figures
  /// from before it.
  void Post(viscera_proto::session_status_t* status, int8_t new_state = -1);

  int8_t state() const { return state_.load(); }
  /// Sets the state without posting figures (the loop is over or never ran).
  void set_state(int8_t state) { state_ = state; }

 private:
  std::atomic<double> step_slack_{1.0};
  std::atomic<int8_t> state_{viscera_proto::session_status_t::kRunning};
  std::atomic<int64_t> poses_{0};
  std::atomic<int64_t> rejected_{0};
  std::atomic<int64_t> replayed_{0};

  mutable std::mutex status_mutex_;  // guards status_, last_error_, frames_seen_
  viscera_proto::session_status_t status_;
  mutable std::string last_error_;         // Read() folds the render thread's new problems in
  mutable FrameStreamReport frames_seen_;  // the last report Read() could take
  mutable std::mutex frames_mutex_;        // render thread; others only try_lock it
  FrameStreamReport frames_;
};

}  // namespace viscera::session
