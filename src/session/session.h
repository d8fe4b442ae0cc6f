#pragma once
/// Session: one running simulation. It owns the immutable model, the mechanics thread (a
/// fixed-rate loop with absolute deadlines), the inbox the I/O thread fills, and the
/// session record. Every step it publishes force feedback; at configured rates, skeleton
/// state and status. An exception never leaves the mechanics thread: the loop catches it,
/// marks the session faulted and says why in its status; the server lives on.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <viscera_proto/session_status_t.hpp>

#include "assessment/metrics.h"
#include "assessment/report.h"
#include "bus/lcm_bus.h"
#include "common/clock.h"
#include "mechanics/model.h"
#include "session/inbox.h"
#include "session/recorder.h"
#include "session/snapshot.h"

namespace viscera::session {

struct SessionConfig {
  int64_t id = 0;                  ///< session id (> 0)
  std::vector<uint8_t> token;      ///< session token every message must carry
  std::string server_id;           ///< for status messages
  std::string scene;               ///< scene label for status ("fall", "<inline>")
  double skeleton_rate_hz = 30.0;  ///< skeleton_state_t per second; <= 0: none
  double status_rate_hz = 4.0;     ///< session_status_t per second (> 0)
  /// Skeleton snapshots handed to readers (the render thread) per second (> 0); the
  /// mechanics rate while frames stream, so that a frame shows the pose of its tick.
  double snapshot_rate_hz = 30.0;
  /// > 0: the mechanics thread runs SCHED_FIFO one above this priority and its output
  /// thread at it (1..98), so builds, other processes and the server's other threads cannot
  /// delay its steps; 0: normal scheduling.
  int realtime_priority = 0;
  /// The session ends when its client sends nothing for this long (s); <= 0: never. The
  /// server enforces it (Expired); the status reports the time left.
  double lease_s = 0.0;
  /// The mechanics loop sleeps until this long before each deadline, then spins (ns; at most
  /// half a period); < 0: AutoSpinNs (common/pacer.h and docs/haptics.md, "Pacing", say why).
  int64_t spin_ns = -1;
};

/// Thread-safe view of a session's camera (set by kCamera, read by a render thread).
struct CameraPose {
  Vec3 eye{0.0, -0.3, 0.3};
  Vec3 target = Vec3::Zero();
  Vec3 up = Vec3::UnitZ();
  double fov_deg = 60.0;
  /// False until a client sets the camera: the render thread then frames the scene itself.
  bool set_by_client = false;
};

/// What a session's render thread reports of its frame stream; merged into every status.
struct FrameStreamReport {
  std::string error;         ///< the render thread's last problem ("" if none)
  int64_t error_serial = 0;  ///< +1 per new error: Status() takes each one once
  std::string skin;
  int width = 0, height = 0;                        ///< pixels
  double rate_hz = 0.0;                             ///< configured (Hz)
  double achieved_rate_hz = 0.0;                    ///< over about the last second (Hz)
  int64_t frames = 0;                               ///< sent
  int64_t dropped = 0;                              ///< skipped: the renderer was busy
  float skin_ms = 0, render_ms = 0, encode_ms = 0;  ///< medians over about the last second
  int32_t frame_bytes = 0;                          ///< JPEG size of the last frame rendered
};

class Session {
 public:
  /// @pre config.id > 0, config.status_rate_hz > 0; model, bus outlive nothing here:
  ///      the session keeps the model alive and `bus` must outlive the session.
  /// @param recorder the session record, or nullptr for none.
  Session(SessionConfig config, std::shared_ptr<const mechanics::Model> model, bus::LcmBus* bus,
          std::unique_ptr<Recorder> recorder);
  /// Stops the thread if it runs.
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  /// Starts the mechanics thread. @pre not started before.
  void Start();
  /// Stops the mechanics thread (within one period), publishes and records a final
  /// kStopped status and flushes the record. Idempotent.
  void Stop();

  const SessionConfig& config() const { return config_; }
  const mechanics::Model& model() const { return *model_; }
  int num_tools() const { return static_cast<int>(model_->params().tools.size()); }
  Inbox& inbox() { return inbox_; }
  /// nullptr when the session keeps no record.
  Recorder* recorder() { return recorder_.get(); }

  /// Counts a message of this session dropped as invalid (any thread), keeping `why` as
  /// the last error.
  void CountRejected(const std::string& why);
  /// Keeps the render thread's latest figures (and problems) for the status. Any thread;
  /// the mechanics thread never waits for the lock this takes (Status() says how).
  void ReportFrames(const FrameStreamReport& report);
  /// Keeps an exposure of target `index` (0..1) evaluated on the pose at simulated time
  /// `sim_time` (the exposure watcher's thread). The mechanics thread never waits for it.
  void ReportExposure(int index, double exposure, double sim_time);
  /// The assessment so far (any thread; the final one once Stop() returned). Also written as
  /// JSON next to the session's record when the session stops (AssessmentPath()).
  assessment::Report Assessment() const;
  /// Where the final assessment is written: the record's path with `.assessment.json` for
  /// `.lcmlog`; "" without a record.
  std::string AssessmentPath() const;
  /// Counts an accepted pose (I/O thread).
  void CountPose() { ++poses_; }
  /// Keeps `why` as the last error (shown in status), counting nothing. Any thread.
  void SetError(const std::string& why);
  /// Counts a replayed or stale message of this session (also a rejected one).
  void CountReplayed(const std::string& why);
  /// Renews the lease: the client sent an authentic pose, command or keep-alive (any thread).
  void Touch() { last_touch_ns_ = MonotonicNanos(); }
  /// Renews the frame lease: someone watches the frames (any thread).
  void WatchFrames() { last_watch_ns_ = MonotonicNanos(); }
  /// True while a viewer renewed the frame lease within `lease_ns` of `now_ns` (monotonic).
  bool FramesWatched(int64_t now_ns, int64_t lease_ns) const {
    const int64_t last = last_watch_ns_.load();
    return last != kNeverWatched && now_ns - last <= lease_ns;
  }
  /// Lease time left (s) at monotonic time `now_ns`; +infinity without a lease.
  double LeaseLeft(int64_t now_ns) const;

  /// The latest status (refreshed at status rate and on every state change).
  viscera_proto::session_status_t Status() const;
  CameraPose camera() const;
  /// Sets the laparoscope camera (I/O thread; the render thread reads it). The mechanics
  /// thread never takes the lock behind it.
  void SetCamera(const CameraPose& pose);
  /// The latest skeleton snapshot (published at config().snapshot_rate_hz), for the
  /// skin/render thread. Any thread.
  std::shared_ptr<const Snapshot> LatestSnapshot() const { return snapshots_.Latest(); }
  bool faulted() const { return state_.load() == viscera_proto::session_status_t::kFaulted; }

 private:
  void Run();
  void Loop(bool realtime);
  void ApplyCommands();
  void PublishForces(int64_t now_ns);
  void PublishSkeleton();
  /// Publishes the status; `new_state` (>= 0) becomes the session's state in the same critical
  /// section as the figures, so no reader sees the new state with figures from before it.
  void PublishStatus(int64_t now_ns, bool summarize, int8_t new_state = -1);
  // The assessment of the mechanics thread's metrics and the latest exposures, into status_.
  void FillAssessment(viscera_proto::session_status_t* status);
  void WriteAssessment();

  SessionConfig config_;
  std::shared_ptr<const mechanics::Model> model_;
  bus::LcmBus* bus_;
  std::unique_ptr<Recorder> recorder_;
  Inbox inbox_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<int8_t> state_{viscera_proto::session_status_t::kRunning};
  std::atomic<int64_t> poses_{0};
  std::atomic<int64_t> rejected_{0};
  std::atomic<int64_t> replayed_{0};
  std::atomic<int64_t> last_touch_ns_;
  static constexpr int64_t kNeverWatched = INT64_MIN;
  std::atomic<int64_t> last_watch_ns_{kNeverWatched};

  // The render thread (SCHED_IDLE) never takes status_mutex_ or blocks the mechanics thread:
  // a thread that low, preempted while holding a lock, could hold it for a long time.
  mutable std::mutex status_mutex_;           // guards status_, last_error_, frames_seen_
  viscera_proto::session_status_t status_{};  // zeroed: lcm-gen types leave counters uninitialized
  mutable std::string last_error_;            // Status() folds the render thread's new problems in
  mutable FrameStreamReport frames_seen_;     // the last report Status() could read
  mutable std::mutex camera_mutex_;           // I/O and render threads only
  CameraPose camera_;
  mutable std::mutex frames_mutex_;  // render thread; others only try_lock it
  FrameStreamReport frames_;
  SnapshotExchange snapshots_;
  mutable std::mutex exposure_mutex_;  // the exposure watcher; the mechanics thread try_locks
  assessment::TargetTracker targets_;  // guarded by exposure_mutex_
  assessment::Report targets_seen_;    // mechanics thread: the last targets it could read

  // Mechanics thread only (the loop and what it calls).
  struct LoopState;
  std::unique_ptr<LoopState> loop_;
};

}  // namespace viscera::session
