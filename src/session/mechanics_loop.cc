#include "session/mechanics_loop.h"

#include <algorithm>
#include <cmath>

#include "assessment/status_report.h"
#include "bus/channels.h"
#include "bus/header.h"
#include "common/check.h"
#include "common/clock.h"
#include "common/pacer.h"
#include "mechanics/forces.h"
#include "session/force_feedback.h"
#include "session/session.h"
#include "session/step_record.h"

namespace viscera::session {

using viscera_proto::session_status_t;

namespace {

int64_t PeriodNs(double rate_hz) { return static_cast<int64_t>(std::llround(1e9 / rate_hz)); }

}  // namespace

MechanicsLoop::MechanicsLoop(Parts parts)
    : parts_(std::move(parts)),
      stepper_(*parts_.model),
      targets_(parts_.model->params().tools.size()),
      was_active_(parts_.model->params().tools.size(), false),
      metrics_(parts_.model->params()),
      skeleton_(parts_.config->id) {}

void MechanicsLoop::Run(const std::atomic<bool>& stop, bool realtime) {
  const SessionConfig& config = *parts_.config;
  const mechanics::Model& model = *parts_.model;
  commands_.reserve(Inbox::kMaxCommands);
  outbox_ = std::make_unique<Outbox>(
      parts_.bus, parts_.recorder,
      Outbox::Channels{bus::SessionChannel(bus::kForcePrefix, config.id),
                       bus::SessionChannel(bus::kSkeletonPrefix, config.id),
                       bus::SessionChannel(bus::kStatusPrefix, config.id),
                       bus::SessionChannel(bus::kStepPrefix, config.id)},
      config.realtime_priority);

  const int64_t period = PeriodNs(model.params().rate_hz);
  const int64_t status_period = PeriodNs(config.status_rate_hz);
  const bool send_skeleton = config.skeleton_rate_hz > 0.0;
  const int64_t skeleton_period = PeriodNs(send_skeleton ? config.skeleton_rate_hz : 1.0);
  const int64_t snapshot_period = PeriodNs(config.snapshot_rate_hz);
  // a first status at once (no rates yet), then one per status period
  parts_.publish_status(MonotonicNanos(), /*summarize=*/false, -1);
  // absolute deadlines, sleep then (under SCHED_FIFO) spin: common/pacer.h
  const int64_t spin = config.spin_ns >= 0 ? config.spin_ns : AutoSpinNs(realtime);
  Pacer pacer({.period_ns = period, .spin_ns = std::min(spin, period / 2)});
  pacer.Start();
  int64_t next = pacer.deadline();
  int64_t next_skeleton = next;
  int64_t next_snapshot = next;
  last_summary_ns_ = next;
  int64_t next_status = next + status_period;

  while (!stop.load(std::memory_order_relaxed)) {
    next = pacer.deadline();
    const int64_t wake = pacer.Wait();

    // commands first (in arrival order), then a step with the latest poses
    parts_.inbox->Take(&poses_, &commands_);
    ApplyCommands();
    if (!paused_) {
      // targets: latest pose per tool; a tool without a recent pose goes idle
      for (size_t i = 0; i < targets_.size(); ++i) {
        const PoseInput& p = poses_[i];
        const double idle_s = model.params().tools[i].idle_timeout;
        const bool active =
            p.seq >= 0 && static_cast<double>(wake - p.received_ns) * 1e-9 <= idle_s;
        if (was_active_[i] && !active) ++idle_events_;
        was_active_[i] = active;
        targets_[i] = p.target;
        targets_[i].active = active;
      }

      PushStepRecord(viscera_proto::step_record_t::kStep, targets_, poses_);
      const int64_t cpu0 = ThreadCpuNanos();
      if (stepper_.Advance(targets_)) {
        parts_.board->SetError(Cat("mechanics blew up at t = ", stepper_.state().t,
                                   " s: restored the last good state"));
      }
      stats_.RecordStep(ThreadCpuNanos() - cpu0, wake - next);
      AssessStep();
      PublishForces();
    }

    const int64_t now = MonotonicNanos();
    if (now >= next_snapshot) {
      parts_.snapshots->Publish(stepper_.state(), damaged_);
      next_snapshot = std::max(next_snapshot + snapshot_period, now);
    }
    if (send_skeleton && now >= next_skeleton) {
      outbox_->Push(skeleton_.Fill(model, stepper_.state()));
      next_skeleton = std::max(next_skeleton + skeleton_period, now);
    }
    if (now >= next_status) {
      parts_.publish_status(now, /*summarize=*/true, -1);
      next_status = std::max(next_status + status_period, now);
    }

    outbox_->Flush();
    const int64_t done = MonotonicNanos();
    const bool missed = pacer.Advance(done);
    if (!paused_) {
      stats_.RecordWall(done - next);
      if (missed) stats_.RecordMiss();
    }
  }
}

void MechanicsLoop::AssessStep() {
  // the camera the frames are drawn from, when the exposure watcher reported a new one
  if (assessment::View view; parts_.targets->TakeView(&view)) metrics_.SetView(view);
  metrics_.AddStep(stepper_.state(), parts_.model->step_size());
  // running the bowel's damaged parts for the frames, anew only when a damage event came
  if (const assessment::RunningScore* running = metrics_.running();
      running != nullptr && running->damage().events().size() != damage_events_) {
    damage_events_ = running->damage().events().size();
    damaged_ = running->damage().DamagedRanges();
  }
}

void MechanicsLoop::ApplyCommands() {
  for (const Command& c : commands_) {
    switch (c.kind) {
      case Command::Kind::kReset:
        stepper_.Reset();
        PushStepRecord(viscera_proto::step_record_t::kReset, {}, {});
        break;
      // the state and the figures at the moment it changed, in one status: a client that sees
      // "paused" reads the figures of the last step taken
      case Command::Kind::kPause:
        paused_ = true;
        parts_.publish_status(MonotonicNanos(), /*summarize=*/false, session_status_t::kPaused);
        break;
      case Command::Kind::kResume:
        paused_ = false;
        parts_.publish_status(MonotonicNanos(), /*summarize=*/false, session_status_t::kRunning);
        break;
    }
  }
  commands_.clear();
}

void MechanicsLoop::PushStepRecord(int8_t kind, std::span<const mechanics::ToolTarget> targets,
                                   std::span<const PoseInput> poses) {
  if (parts_.recorder == nullptr) return;
  FillStepRecord(kind, stepper_.state().steps, targets, poses, &record_);
  record_.header = bus::MakeHeader(parts_.config->id, record_seq_++);
  outbox_->Push(record_);
}

void MechanicsLoop::PublishForces() {
  const mechanics::State& s = stepper_.state();
  for (size_t i = 0; i < s.tools.size(); ++i) {
    viscera_proto::force_feedback_t& f = force_;
    f.header = bus::MakeHeader(parts_.config->id, force_seq_++);
    FillForceFeedback(s, i, targets_[i], poses_.size() > i ? poses_[i].seq : -1, &f);
    f.pose_utime = poses_.size() > i ? poses_[i].client_utime : 0;
    outbox_->Push(f);
  }
}

void MechanicsLoop::AddFigures(int64_t now_ns, bool summarize, session_status_t* status) {
  session_status_t& s = *status;
  const mechanics::State& st = stepper_.state();
  s.sim_time = st.t;
  s.steps = st.steps;
  if (summarize) {
    const LoopSummary sum = stats_.Summarize(now_ns - last_summary_ns_);
    last_summary_ns_ = now_ns;
    if (paused_) {
      rate_window_.Clear();
    } else {
      rate_window_.Add(now_ns, st.steps);
      s.achieved_rate_hz = rate_window_.ready() ? rate_window_.Rate() : sum.achieved_rate_hz;
    }
    s.step_cost_p50_us = sum.step_cost_p50_us;
    s.step_cost_p99_us = sum.step_cost_p99_us;
    s.jitter_p99_us = sum.jitter_p99_us;
    s.step_wall_max_us = sum.wall_max_us;
    parts_.board->SetStepSlack(StepSlack(sum, s.rate_hz));
  }
  if (paused_) s.achieved_rate_hz = 0.0;  // the periodic statuses and the one a pause publishes
  s.deadline_misses = stats_.deadline_misses();
  s.energy = mechanics::ComputeEnergies(*parts_.model, st.q, st.qd).total();
  s.contacts = st.contacts.self + st.contacts.environment + st.contacts.tool;
  s.recoveries = stepper_.recoveries();
  s.unconverged_solves = st.unconverged_solves;  // the stepper keeps it through recoveries
  s.idle_events = idle_events_;
  if (outbox_ != nullptr) {
    s.messages_dropped = outbox_->dropped();
    s.nonfinite_dropped = outbox_->nonfinite();
  }
  if (parts_.recorder != nullptr) s.record_failures = parts_.recorder->failures();
  // the assessment of the loop's metrics and the latest exposures
  assessment::Report report;
  metrics_.Fill(&report);
  parts_.targets->FillForStatus(
      /*may_wait=*/parts_.board->state() == session_status_t::kStopped, &report);
  assessment::FillStatus(report, &s);
}

bool MechanicsLoop::Send(const session_status_t& status) {
  if (outbox_ == nullptr) return false;
  outbox_->Push(status);
  outbox_->Flush();
  return true;
}

}  // namespace viscera::session
