#pragma once
/// MechanicsLoop: a session's fixed-rate loop (absolute deadlines, common/pacer.h) and all
/// it owns. Built on the mechanics thread and touched by no other thread while it runs;
/// the session reads it again only once the thread has ended. Each step it takes the
/// inbox's commands and poses, steps the model and queues force feedback on its outbox; at
/// their rates it hands skeleton snapshots to readers and publishes skeleton and status.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <viscera_proto/force_feedback_t.hpp>
#include <viscera_proto/session_status_t.hpp>
#include <viscera_proto/step_record_t.hpp>

#include "assessment/metrics.h"
#include "bus/lcm_bus.h"
#include "common/rate_window.h"
#include "mechanics/model.h"
#include "session/assessment_file.h"
#include "session/inbox.h"
#include "session/loop_stats.h"
#include "session/outbox.h"
#include "session/recorder.h"
#include "session/skeleton_message.h"
#include "session/snapshot.h"
#include "session/status_board.h"
#include "session/stepper.h"

namespace viscera::session {

struct SessionConfig;

class MechanicsLoop {
 public:
  /// Publishes a status (Session::PublishStatus): the time, whether to take the loop's
  /// figures over the last status period, and the state it brings (< 0: unchanged).
  using PublishStatus = std::function<void(int64_t now_ns, bool summarize, int8_t new_state)>;

  /// What the loop works with; each outlives the loop.
  struct Parts {
    const SessionConfig* config;
    const mechanics::Model* model;
    bus::LcmBus* bus;
    Recorder* recorder;  ///< nullptr: no record
    Inbox* inbox;
    SnapshotExchange* snapshots;
    StatusBoard* board;  ///< for the loop's errors
    TargetExposures* targets;
    PublishStatus publish_status;
  };

  explicit MechanicsLoop(Parts parts);

  /// Steps until `stop` is set. `realtime`: the thread runs SCHED_FIFO (the pacer spins).
  void Run(const std::atomic<bool>& stop, bool realtime);

  /// The loop's figures into `status`: time, steps, rates, costs, energy, counters and the
  /// assessment. `summarize`: the rates and costs over the last status period (they restart).
  void AddFigures(int64_t now_ns, bool summarize, viscera_proto::session_status_t* status);
  /// Queues `status` on the outbox and wakes it; false when there is no outbox (yet).
  bool Send(const viscera_proto::session_status_t& status);
  /// Sends what the outbox holds and ends its thread.
  void CloseOutbox() { outbox_.reset(); }

 private:
  void ApplyCommands();
  /// Feeds the step just taken to the assessment (with the latest camera), and keeps running
  /// the bowel's damaged parts for the snapshots.
  void AssessStep();
  void PublishForces();
  /// Records the step (or reset) about to happen, when the session keeps a record.
  void PushStepRecord(int8_t kind, std::span<const mechanics::ToolTarget> targets,
                      std::span<const PoseInput> poses);

  Parts parts_;
  Stepper stepper_;
  LoopStats stats_;
  std::vector<PoseInput> poses_;
  std::vector<Command> commands_;
  std::vector<mechanics::ToolTarget> targets_;
  std::vector<bool> was_active_;
  /// The assessment's per-step figures (fed after each step, never inside it).
  assessment::SessionMetrics metrics_;
  /// Running the bowel's damaged parts (ranges of s) handed to readers with each snapshot, and
  /// the damage events they were taken at.
  std::vector<std::pair<double, double>> damaged_;
  size_t damage_events_ = 0;
  bool paused_ = false;
  int64_t idle_events_ = 0;
  int64_t force_seq_ = 0, record_seq_ = 0;
  viscera_proto::force_feedback_t force_;
  viscera_proto::step_record_t record_;
  SkeletonMessage skeleton_;
  int64_t last_summary_ns_ = 0;
  /// Steps at recent statuses: the achieved rate is taken over about 1 s.
  RateWindow rate_window_;
  /// Publishes and records off this thread, in order (outbox.h says why).
  std::unique_ptr<Outbox> outbox_;
};

}  // namespace viscera::session
