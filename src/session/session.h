#pragma once
/// Session: one running simulation. It owns the immutable model, the mechanics thread (its
/// loop: mechanics_loop.h), the inbox the I/O thread fills, and the session record; what
/// other threads read of it sits on its status board (status_board.h), its camera, its
/// skeleton snapshots and its targets' exposures (assessment_file.h). Every step it publishes
/// force feedback; at configured rates, skeleton state and status. An exception never leaves
/// the mechanics thread: the session catches it, marks itself faulted and says why in its
/// status; the server lives on.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <viscera_proto/session_status_t.hpp>

#include "assessment/report.h"
#include "bus/lcm_bus.h"
#include "common/clock.h"
#include "mechanics/model.h"
#include "session/assessment_file.h"
#include "session/inbox.h"
#include "session/recorder.h"
#include "session/snapshot.h"
#include "session/status_board.h"

namespace viscera::session {

class MechanicsLoop;

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
  /// Keeps the camera the frames are drawn from, as the exposure watcher judges the targets
  /// from it (its thread): running the bowel's camera coverage and time out of view are judged
  /// from it too. The mechanics thread never waits for it.
  void ReportView(const assessment::View& view) { targets_.SetView(view); }
  /// The assessment so far (any thread; the final one once Stop() returned). Also written as
  /// JSON next to the session's record when the session stops (AssessmentPath()).
  assessment::Report Assessment() const;
  /// Where the final assessment is written: the record's path with `.assessment.json` for
  /// `.lcmlog`; "" without a record.
  std::string AssessmentPath() const;
  /// Counts an accepted pose (I/O thread).
  void CountPose() { board_.CountPose(); }
  /// Keeps `why` as the last error (shown in status), counting nothing. Any thread.
  void SetError(const std::string& why);
  /// Counts a replayed or stale message of this session (also a rejected one).
  void CountReplayed(const std::string& why);
  /// Renews the lease: the client sent an authentic pose, command or keep-alive (any thread).
  void Touch() { last_touch_ns_ = MonotonicNanos(); }
  /// Renews the frame lease: someone watches the frames (any thread).
  void WatchFrames() { last_watch_ns_ = MonotonicNanos(); }
  /// The mechanics' step slack (StatusBoard::step_slack): lock-free, for the render thread.
  double step_slack() const { return board_.step_slack(); }
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
  bool faulted() const { return board_.state() == viscera_proto::session_status_t::kFaulted; }

 private:
  void Run();
  /// Publishes the status (from the mechanics thread, or once it has ended): the board's,
  /// with the loop's figures when it ran; `new_state` (>= 0) becomes the session's state
  /// with them (StatusBoard::Post).
  void PublishStatus(int64_t now_ns, bool summarize, int8_t new_state = -1);
  void WriteAssessment();

  SessionConfig config_;
  std::shared_ptr<const mechanics::Model> model_;
  bus::LcmBus* bus_;
  std::unique_ptr<Recorder> recorder_;
  Inbox inbox_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> last_touch_ns_;
  static constexpr int64_t kNeverWatched = INT64_MIN;
  std::atomic<int64_t> last_watch_ns_{kNeverWatched};

  // What other threads read, each behind its own lock (the class says whose): the mechanics
  // thread waits for none that a low-priority thread (render, exposure watcher) takes.
  StatusBoard board_;
  mutable std::mutex camera_mutex_;  // I/O and render threads only
  CameraPose camera_;
  SnapshotExchange snapshots_;
  TargetExposures targets_;

  // The mechanics thread's alone while it runs (built there); the session's once it ended.
  std::unique_ptr<MechanicsLoop> loop_;
};

}  // namespace viscera::session
