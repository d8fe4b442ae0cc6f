#include "session/session.h"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <cstdio>
#include <cstring>

#include <algorithm>
#include <cmath>
#include <exception>
#include <fstream>
#include <limits>
#include <utility>

#include <viscera_proto/force_feedback_t.hpp>
#include <viscera_proto/skeleton_state_t.hpp>
#include <viscera_proto/step_record_t.hpp>

#include "assessment/status_report.h"
#include "bus/channels.h"
#include "bus/header.h"
#include "common/check.h"
#include "common/clock.h"
#include "common/pacer.h"
#include "common/rate_window.h"
#include "mechanics/forces.h"
#include "session/force_feedback.h"
#include "session/loop_stats.h"
#include "session/outbox.h"
#include "session/step_record.h"
#include "session/stepper.h"
#include "spline/arc_length.h"

namespace viscera::session {

using viscera_proto::session_status_t;

namespace {

int64_t PeriodNs(double rate_hz) { return static_cast<int64_t>(std::llround(1e9 / rate_hz)); }

}  // namespace

/// Everything the mechanics thread owns: built on the thread, never touched by others.
struct Session::LoopState {
  explicit LoopState(const mechanics::Model& model, int num_tools)
      : stepper(model),
        targets(static_cast<size_t>(num_tools)),
        was_active(num_tools, false),
        metrics(model.params()) {}

  Stepper stepper;
  LoopStats stats;
  std::vector<PoseInput> poses;
  std::vector<Command> commands;
  std::vector<mechanics::ToolTarget> targets;
  std::vector<bool> was_active;
  /// The assessment's per-step figures (fed after each step, never inside it).
  assessment::SessionMetrics metrics;
  bool paused = false;
  int64_t idle_events = 0;
  int64_t force_seq = 0, skeleton_seq = 0, status_seq = 0, record_seq = 0;
  viscera_proto::force_feedback_t force;
  viscera_proto::skeleton_state_t skeleton;
  viscera_proto::step_record_t record;
  spline::ArcLengthTable arc_table;
  int64_t last_summary_ns = 0;
  std::string force_channel, skeleton_channel, status_channel, step_channel;
  /// Steps at recent statuses: the achieved rate is taken over about 1 s.
  RateWindow rate_window;
  /// Publishes and records off this thread, in order (outbox.h says why).
  std::unique_ptr<Outbox> outbox;
};

Session::Session(SessionConfig config, std::shared_ptr<const mechanics::Model> model,
                 bus::LcmBus* bus, std::unique_ptr<Recorder> recorder)
    : config_(std::move(config)),
      model_(std::move(model)),
      bus_(bus),
      recorder_(std::move(recorder)),
      inbox_(static_cast<int>(model_->params().tools.size())),
      last_touch_ns_(MonotonicNanos()),
      targets_(model_->params().task) {
  VISCERA_DEMAND(config_.id > 0 && config_.status_rate_hz > 0.0 && config_.snapshot_rate_hz > 0.0 &&
                 bus_ != nullptr);
  status_.header = bus::MakeHeader(config_.id, 0);
  status_.server_id = config_.server_id;
  status_.scene = config_.scene;
  status_.num_tools = num_tools();
  for (const mechanics::ToolParams& t : model_->params().tools)
    status_.tool_names.push_back(t.name);
  status_.state = session_status_t::kRunning;
  status_.rate_hz = model_->params().rate_hz;
  // the assessment's arrays are sized by num_tools and num_targets from the first status on
  assessment::Report empty;
  assessment::SessionMetrics(model_->params()).Fill(&empty);
  targets_.Fill(&empty);
  assessment::FillStatus(empty, &status_);
}

Session::~Session() { Stop(); }

void Session::Start() {
  VISCERA_DEMAND(!thread_.joinable());
  thread_ = std::thread([this] { Run(); });
}

void Session::Stop() {
  if (stop_.exchange(true)) return;
  if (thread_.joinable()) thread_.join();
  // the loop is over: its state is ours now. A last status, recorded, and the record flushed.
  state_ = session_status_t::kStopped;
  try {
    PublishStatus(MonotonicNanos(), /*summarize=*/false);
  } catch (const std::exception& e) {
    SetError(Cat("final status failed: ", e.what()));
  }
  if (loop_ != nullptr) loop_->outbox.reset();  // sends what is queued, joins its thread
  if (recorder_ != nullptr) recorder_->Flush();
  WriteAssessment();
}

void Session::ReportExposure(int index, double exposure, double sim_time) {
  std::lock_guard<std::mutex> lock(exposure_mutex_);
  targets_.Add(index, exposure, sim_time);
}

assessment::Report Session::Assessment() const { return assessment::ReportFromStatus(Status()); }

std::string Session::AssessmentPath() const {
  if (recorder_ == nullptr) return "";
  std::string path = recorder_->path();
  const std::string ext = ".lcmlog";
  if (path.size() > ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0) {
    path.resize(path.size() - ext.size());
  }
  return path + ".assessment.json";
}

void Session::WriteAssessment() {
  const std::string path = AssessmentPath();
  if (path.empty()) return;
  // write then rename: a reader never sees half a report
  const std::string partial = path + ".partial";
  {
    std::ofstream out(partial);
    out << assessment::ToJson(Assessment()).dump(2) << "\n";
    if (!out) {
      SetError(Cat("assessment not written to ", path));
      return;
    }
  }
  if (std::rename(partial.c_str(), path.c_str()) != 0)
    SetError(Cat("assessment not written to ", path));
}

void Session::FillAssessment(session_status_t* status) {
  LoopState& L = *loop_;
  assessment::Report report;
  L.metrics.Fill(&report);
  {
    // never wait for the exposure watcher: if it holds the lock, the targets last read serve
    std::unique_lock<std::mutex> lock(exposure_mutex_, std::try_to_lock);
    if (lock.owns_lock() || state_.load() == session_status_t::kStopped) {
      if (!lock.owns_lock()) lock.lock();  // the loop is over: waiting delays no step
      targets_.Fill(&targets_seen_);
    }
  }
  report.targets = targets_seen_.targets;
  assessment::FillStatus(report, status);
}

void Session::CountRejected(const std::string& why) {
  ++rejected_;
  SetError(why);
}

void Session::CountReplayed(const std::string& why) {
  ++replayed_;
  CountRejected(why);
}

double Session::LeaseLeft(int64_t now_ns) const {
  if (config_.lease_s <= 0.0) return std::numeric_limits<double>::infinity();
  return config_.lease_s - static_cast<double>(now_ns - last_touch_ns_.load()) * 1e-9;
}

void Session::SetError(const std::string& why) {
  std::lock_guard<std::mutex> lock(status_mutex_);
  last_error_ = why;
}

void Session::ReportFrames(const FrameStreamReport& report) {
  std::lock_guard<std::mutex> lock(frames_mutex_);
  frames_ = report;
}

session_status_t Session::Status() const {
  std::lock_guard<std::mutex> lock(status_mutex_);
  {
    // never wait for the render thread: if it holds the lock, the last report read serves
    std::unique_lock<std::mutex> frames_lock(frames_mutex_, std::try_to_lock);
    if (frames_lock.owns_lock()) {
      if (frames_.error_serial != frames_seen_.error_serial) {
        last_error_ = frames_.error;  // a new render problem
      }
      frames_seen_ = frames_;
    }
  }
  session_status_t s = status_;
  s.state = state_.load();
  s.poses = poses_.load();
  s.rejected = rejected_.load();
  s.replayed = replayed_.load();
  s.lease_s = std::max(config_.lease_s, 0.0);
  s.lease_left_s = config_.lease_s > 0.0 ? std::max(LeaseLeft(MonotonicNanos()), 0.0) : 0.0;
  s.last_error = last_error_;
  s.skin = frames_seen_.skin;
  s.frame_width = frames_seen_.width;
  s.frame_height = frames_seen_.height;
  s.frame_rate_hz = frames_seen_.rate_hz;
  s.achieved_frame_rate_hz = frames_seen_.achieved_rate_hz;
  s.frames = frames_seen_.frames;
  s.frames_dropped = frames_seen_.dropped;
  s.skin_ms = frames_seen_.skin_ms;
  s.render_ms = frames_seen_.render_ms;
  s.encode_ms = frames_seen_.encode_ms;
  s.frame_bytes = frames_seen_.frame_bytes;
  return s;
}

CameraPose Session::camera() const {
  std::lock_guard<std::mutex> lock(camera_mutex_);
  return camera_;
}

void Session::SetCamera(const CameraPose& pose) {
  std::lock_guard<std::mutex> lock(camera_mutex_);
  camera_ = pose;
}

void Session::Run() {
  bool realtime = false;
  if (config_.realtime_priority > 0) {
    sched_param param{};
    // one above the I/O, LCM and output threads (which run at realtime_priority): on two
    // cores a step must not wait for them to block
    param.sched_priority = std::min(99, config_.realtime_priority + 1);
    if (const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param); err != 0) {
      SetError(Cat("realtime priority refused (", std::strerror(err), "): normal scheduling"));
    } else {
      realtime = true;
    }
  }
  // An exception never crosses a thread: the session is faulted, the daemon lives on.
  try {
    loop_ = std::make_unique<LoopState>(*model_, num_tools());
    Loop(realtime);
  } catch (const std::exception& e) {
    SetError(Cat("mechanics thread failed: ", e.what()));
    state_ = session_status_t::kFaulted;
  } catch (...) {
    SetError("mechanics thread failed with a non-std exception");
    state_ = session_status_t::kFaulted;
  }
  if (state_.load() == session_status_t::kFaulted) {
    try {
      PublishStatus(MonotonicNanos(), /*summarize=*/false);
    } catch (...) {
      // nothing more can be said
    }
  }
}

void Session::Loop(bool realtime) {
  LoopState& L = *loop_;
  L.force_channel = bus::SessionChannel(bus::kForcePrefix, config_.id);
  L.skeleton_channel = bus::SessionChannel(bus::kSkeletonPrefix, config_.id);
  L.status_channel = bus::SessionChannel(bus::kStatusPrefix, config_.id);
  L.step_channel = bus::SessionChannel(bus::kStepPrefix, config_.id);
  L.commands.reserve(Inbox::kMaxCommands);
  L.outbox = std::make_unique<Outbox>(
      bus_, recorder_.get(),
      Outbox::Channels{L.force_channel, L.skeleton_channel, L.status_channel, L.step_channel},
      config_.realtime_priority);

  const int64_t period = PeriodNs(model_->params().rate_hz);
  const int64_t status_period = PeriodNs(config_.status_rate_hz);
  const bool send_skeleton = config_.skeleton_rate_hz > 0.0;
  const int64_t skeleton_period = PeriodNs(send_skeleton ? config_.skeleton_rate_hz : 1.0);
  const int64_t snapshot_period = PeriodNs(config_.snapshot_rate_hz);
  // a first status at once (no rates yet), then one per status period
  PublishStatus(MonotonicNanos(), /*summarize=*/false);
  // absolute deadlines, sleep then (under SCHED_FIFO) spin: common/pacer.h
  const int64_t spin = config_.spin_ns >= 0 ? config_.spin_ns : AutoSpinNs(realtime);
  Pacer pacer({.period_ns = period, .spin_ns = std::min(spin, period / 2)});
  pacer.Start();
  int64_t next = pacer.deadline();
  int64_t next_skeleton = next;
  int64_t next_snapshot = next;
  L.last_summary_ns = next;
  int64_t next_status = next + status_period;

  while (!stop_.load(std::memory_order_relaxed)) {
    next = pacer.deadline();
    const int64_t wake = pacer.Wait();

    // commands first (in arrival order), then a step with the latest poses
    inbox_.Take(&L.poses, &L.commands);
    ApplyCommands();
    if (!L.paused) {
      // targets: latest pose per tool; a tool without a recent pose goes idle
      for (size_t i = 0; i < L.targets.size(); ++i) {
        const PoseInput& p = L.poses[i];
        const double idle_s = model_->params().tools[i].idle_timeout;
        const bool active =
            p.seq >= 0 && static_cast<double>(wake - p.received_ns) * 1e-9 <= idle_s;
        if (L.was_active[i] && !active) ++L.idle_events;
        L.was_active[i] = active;
        L.targets[i] = p.target;
        L.targets[i].active = active;
      }

      if (recorder_ != nullptr) {
        FillStepRecord(viscera_proto::step_record_t::kStep, L.stepper.state().steps, L.targets,
                       L.poses, &L.record);
        L.record.header = bus::MakeHeader(config_.id, L.record_seq++);
        L.outbox->Push(L.record);
      }
      const int64_t cpu0 = ThreadCpuNanos();
      if (L.stepper.Advance(L.targets)) {
        SetError(Cat("mechanics blew up at t = ", L.stepper.state().t,
                     " s: restored the last good state"));
      }
      L.stats.RecordStep(ThreadCpuNanos() - cpu0, wake - next);
      L.metrics.AddStep(L.stepper.state(), model_->step_size());
      PublishForces(wake);
    }

    const int64_t now = MonotonicNanos();
    if (now >= next_snapshot) {
      snapshots_.Publish(L.stepper.state());
      next_snapshot = std::max(next_snapshot + snapshot_period, now);
    }
    if (send_skeleton && now >= next_skeleton) {
      PublishSkeleton();
      next_skeleton = std::max(next_skeleton + skeleton_period, now);
    }
    if (now >= next_status) {
      PublishStatus(now, /*summarize=*/true);
      next_status = std::max(next_status + status_period, now);
    }

    L.outbox->Flush();
    const int64_t done = MonotonicNanos();
    const bool missed = pacer.Advance(done);
    if (!L.paused) {
      L.stats.RecordWall(done - next);
      if (missed) L.stats.RecordMiss();
    }
  }
}

void Session::ApplyCommands() {
  LoopState& L = *loop_;
  for (const Command& c : L.commands) {
    switch (c.kind) {
      case Command::Kind::kReset:
        L.stepper.Reset();
        if (recorder_ != nullptr) {
          FillStepRecord(viscera_proto::step_record_t::kReset, L.stepper.state().steps, {}, {},
                         &L.record);
          L.record.header = bus::MakeHeader(config_.id, L.record_seq++);
          L.outbox->Push(L.record);
        }
        break;
      // the state and the figures at the moment it changed, in one status: a client that sees
      // "paused" reads the figures of the last step taken
      case Command::Kind::kPause:
        L.paused = true;
        PublishStatus(MonotonicNanos(), /*summarize=*/false, session_status_t::kPaused);
        break;
      case Command::Kind::kResume:
        L.paused = false;
        PublishStatus(MonotonicNanos(), /*summarize=*/false, session_status_t::kRunning);
        break;
    }
  }
  L.commands.clear();
}

void Session::PublishForces(int64_t now_ns) {
  (void)now_ns;
  LoopState& L = *loop_;
  const mechanics::State& s = L.stepper.state();
  for (size_t i = 0; i < s.tools.size(); ++i) {
    viscera_proto::force_feedback_t& f = L.force;
    f.header = bus::MakeHeader(config_.id, L.force_seq++);
    FillForceFeedback(s, i, L.targets[i], L.poses.size() > i ? L.poses[i].seq : -1, &f);
    f.pose_utime = L.poses.size() > i ? L.poses[i].client_utime : 0;
    L.outbox->Push(f);
  }
}

void Session::PublishSkeleton() {
  LoopState& L = *loop_;
  const mechanics::State& s = L.stepper.state();
  const mechanics::Model& model = *model_;
  viscera_proto::skeleton_state_t& k = L.skeleton;
  k.header = bus::MakeHeader(config_.id, L.skeleton_seq++);
  k.step = s.steps;
  k.sim_time = s.t;
  k.num_points = static_cast<int32_t>(s.q.rows());
  k.points.resize(static_cast<size_t>(s.q.rows()), std::vector<double>(3));
  for (int i = 0; i < s.q.rows(); ++i) {
    for (int a = 0; a < 3; ++a) k.points[static_cast<size_t>(i)][a] = s.q(i, a);
  }
  // collision spheres: equal spheres spread uniformly by arc length (docs/contacts.md, "Sphere
  // chain")
  const double radius = model.params().radius;
  L.arc_table.Build(model.curve(), s.q);
  const double length = L.arc_table.total_length();
  const int n = std::max(2, static_cast<int>(std::floor(length / (2.0 * radius))) + 1);
  k.num_spheres = n;
  k.spheres.resize(static_cast<size_t>(n), std::vector<double>(3));
  for (int j = 0; j < n; ++j) {
    const double u = L.arc_table.ParameterAt(length * j / (n - 1));
    const Vec3 c = model.curve().Position(s.q, u);
    for (int a = 0; a < 3; ++a) k.spheres[static_cast<size_t>(j)][a] = c(a);
  }
  k.sphere_radius = radius;
  k.environment_contacts = s.contacts.environment;
  k.self_contacts = s.contacts.self;
  k.tool_contacts = s.contacts.tool;
  L.outbox->Push(k);
}

void Session::PublishStatus(int64_t now_ns, bool summarize, int8_t new_state) {
  LoopState* L = loop_.get();
  session_status_t s = Status();
  s.header = bus::MakeHeader(config_.id, s.header.seq + 1);
  if (L != nullptr) {
    const mechanics::State& st = L->stepper.state();
    s.sim_time = st.t;
    s.steps = st.steps;
    if (summarize) {
      const LoopSummary sum = L->stats.Summarize(now_ns - L->last_summary_ns);
      L->last_summary_ns = now_ns;
      if (L->paused) {
        L->rate_window.Clear();
      } else {
        L->rate_window.Add(now_ns, st.steps);
        s.achieved_rate_hz = L->rate_window.ready() ? L->rate_window.Rate() : sum.achieved_rate_hz;
      }
      s.step_cost_p50_us = sum.step_cost_p50_us;
      s.step_cost_p99_us = sum.step_cost_p99_us;
      s.jitter_p99_us = sum.jitter_p99_us;
      s.step_wall_max_us = sum.wall_max_us;
    }
    if (L->paused) s.achieved_rate_hz = 0.0;  // the periodic statuses and the one a pause publishes
    s.deadline_misses = L->stats.deadline_misses();
    s.energy = mechanics::ComputeEnergies(*model_, st.q, st.qd).total();
    s.contacts = st.contacts.self + st.contacts.environment + st.contacts.tool;
    s.recoveries = L->stepper.recoveries();
    s.unconverged_solves = st.unconverged_solves;  // the stepper keeps it through recoveries
    s.idle_events = L->idle_events;
    if (L->outbox != nullptr) {
      s.messages_dropped = L->outbox->dropped();
      s.nonfinite_dropped = L->outbox->nonfinite();
    }
    if (recorder_ != nullptr) s.record_failures = recorder_->failures();
    FillAssessment(&s);
  }
  {
    std::lock_guard<std::mutex> lock(status_mutex_);
    if (new_state >= 0) {
      state_ = new_state;
      s.state = new_state;
    }
    status_ = s;
  }
  if (L != nullptr && L->outbox != nullptr) {
    L->outbox->Push(s);
    L->outbox->Flush();
    return;
  }
  const std::string channel = bus::SessionChannel(bus::kStatusPrefix, config_.id);
  bus_->Publish(channel, s);
  if (recorder_ != nullptr) recorder_->Write(channel, s, s.header.utime);
}

}  // namespace viscera::session
