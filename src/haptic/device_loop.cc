#include "haptic/device_loop.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "common/check.h"
#include "common/clock.h"
#include "common/pacer.h"
#include "common/quantile.h"
#include "haptic/force_limiter.h"
#include "haptic/passivity.h"
#include "haptic/pose_history.h"

namespace viscera::haptic {

namespace {

// The newest `capacity` samples of a figure, for its quantiles (no allocation after start).
class SampleRing {
 public:
  explicit SampleRing(size_t capacity) : values_(capacity) {}
  void Add(double v) {
    values_[count_ % values_.size()] = v;
    ++count_;
  }
  size_t size() const { return std::min(count_, values_.size()); }
  double Quantile(double p) const {
    std::vector<double> copy(values_.begin(), values_.begin() + static_cast<long>(size()));
    return viscera::Quantile(std::move(copy), p);
  }
  double Max() const {
    return size() == 0
               ? 0.0
               : *std::max_element(values_.begin(), values_.begin() + static_cast<long>(size()));
  }
  void Clear() { count_ = 0; }

 private:
  std::vector<double> values_;
  size_t count_ = 0;
};

std::string SetRealtime(int priority) {
  if (priority <= 0) return "off";
  sched_param param{};
  param.sched_priority = std::min(99, priority);
  if (const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param); err != 0) {
    return Cat("refused (", std::strerror(err), "): normal scheduling");
  }
  return Cat("SCHED_FIFO ", param.sched_priority);
}

// `limited`: the model's force after the limits, before the passivity controller's damping
void WriteLogLine(std::FILE* log, double t, const Vec3& x, const Vec3& f, const Vec3& limited,
                  const Vec3& fs, double age_ms, double period_us, double gain, double energy,
                  int64_t nonfinite) {
  std::fprintf(
      log,
      "{\"t\":%.6f,\"position\":[%.9g,%.9g,%.9g],\"force\":[%.9g,%.9g,%.9g],"
      "\"limited_force\":[%.9g,%.9g,%.9g],\"server_force\":[%.9g,%.9g,%.9g],\"model_age_ms\":",
      t, x.x(), x.y(), x.z(), f.x(), f.y(), f.z(), limited.x(), limited.y(), limited.z(), fs.x(),
      fs.y(), fs.z());
  if (std::isfinite(age_ms)) {
    std::fprintf(log, "%.3f", age_ms);
  } else {
    std::fputs("null", log);
  }
  std::fprintf(log, ",\"period_us\":%.1f,\"gain\":%.6f,\"energy_j\":%.9g,\"nonfinite\":%lld}\n",
               period_us, gain, energy, static_cast<long long>(nonfinite));
}

}  // namespace

DeviceLoop::DeviceLoop(Device* device, ForceLink* link, DeviceLoopOptions options)
    : device_(device), link_(link), options_(std::move(options)) {
  VISCERA_DEMAND(device_ != nullptr && link_ != nullptr);
  ThrowUnless(options_.rate_hz > 0.0 && options_.rate_hz <= 20000.0,
              "device loop rate must be within (0, 20000] Hz, got ", options_.rate_hz);
  ThrowUnless(options_.seconds >= 0.0, "--seconds must be >= 0, got ", options_.seconds);
  ThrowUnless(options_.deadband_m >= 0.0 && options_.keepalive_s > 0.0, "deadband ",
              options_.deadband_m, " m must be >= 0 and keep-alive ", options_.keepalive_s,
              " s > 0");
  ThrowUnless(options_.max_force_n >= 0.0, "max force must be >= 0 N, got ", options_.max_force_n);
  options_.impairment.Validate();
}

LoopSummary DeviceLoop::Run() {
  const DeviceLimits limits = device_->limits();
  const double period_s = 1.0 / options_.rate_hz;
  const auto period_ns = static_cast<int64_t>(std::llround(1e9 / options_.rate_hz));

  // what the device can render: its force limit, its stiffness limit and the Colgate bound
  LocalModelOptions model_options = options_.model;
  model_options.period_s = period_s;
  model_options.max_stiffness_n_m =
      std::min({model_options.max_stiffness_n_m, limits.max_stiffness_n_m,
                ColgateStiffnessBound(limits.damping_n_s_m, period_s)});
  const double max_force = options_.max_force_n > 0.0
                               ? std::min(options_.max_force_n, limits.max_force_n)
                               : limits.max_force_n;
  LocalModel model(model_options);
  PassivityController passivity(options_.passivity, limits.max_added_damping_n_s_m);
  ForceLimiter limiter(max_force, options_.max_force_rate_n_s);
  ImpairedChannel<Answer> answers_in(options_.impairment, 1);
  ImpairedChannel<std::pair<int64_t, DeviceSample>> poses_out(options_.impairment, 2);
  PoseHistory history;

  const double seconds = options_.seconds > 0.0 ? options_.seconds : device_->duration();
  const bool forever = seconds <= 0.0;
  const size_t capacity =
      static_cast<size_t>(std::min(600.0, forever ? 600.0 : seconds + 1.0) * options_.rate_hz);
  SampleRing period_error(capacity), round_trip(capacity), model_age(capacity);
  SampleRing window_error(static_cast<size_t>(options_.rate_hz * options_.report_period_s) + 16);
  SampleRing window_trip(window_error.size() + 4096);

  LoopSummary s;
  s.device = device_->name();
  s.rate_hz = options_.rate_hz;
  s.realtime = SetRealtime(options_.realtime_priority);
  s.max_force_n = max_force;
  s.max_force_rate_n_s = options_.max_force_rate_n_s;
  s.max_stiffness_n_m = model_options.max_stiffness_n_m;
  s.passivity = options_.passivity;

  const int64_t spin =
      options_.spin_ns >= 0 ? options_.spin_ns : AutoSpinNs(s.realtime.rfind("SCHED_FIFO", 0) == 0);
  Pacer pacer({.period_ns = period_ns, .spin_ns = std::min(spin, period_ns / 2)});
  pacer.Start();
  const int64_t start = pacer.deadline();
  int64_t prev_wake = 0, last_sent_ns = 0, seq = 0, last_answered_pose = -1;
  int64_t first_step = -1, last_step = -1, device_nonfinite = 0;
  int64_t next_report = start + static_cast<int64_t>(options_.report_period_s * 1e9);
  int64_t window_periods = 0, window_start = start;
  Vec3 x_prev = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  Vec3 x_sent = x_prev;

  auto accept = [&](const Answer& a, int64_t arrived_ns) {
    ++s.answers_received;
    if (a.step >= 0) {
      first_step = first_step < 0 ? a.step : std::min(first_step, a.step);
      last_step = std::max(last_step, a.step);
    }
    const PoseHistory::Entry* pose = history.Find(a.pose_seq);
    if (pose == nullptr) {  // answers a pose this loop never sent (or long forgotten)
      if (!a.force.allFinite() || !a.stiffness.allFinite()) model.FlagNonFinite(arrived_ns);
      ++s.answers_unmatched;
      return;
    }
    if (model.Offer(a, pose->position, pose->sent_ns, arrived_ns) ==
            LocalModel::Intake::kAccepted &&
        a.pose_seq > last_answered_pose) {
      last_answered_pose = a.pose_seq;
      const double rt_us = static_cast<double>(arrived_ns - pose->sent_ns) * 1e-3;
      round_trip.Add(rt_us);
      window_trip.Add(rt_us);
    }
  };

  for (;;) {
    const int64_t wake = pacer.Wait();
    const double t = static_cast<double>(wake - start) * 1e-9;
    if ((!forever && t > seconds) || (options_.stop != nullptr && options_.stop->load())) break;
    const double dt = prev_wake > 0 ? static_cast<double>(wake - prev_wake) * 1e-9 : period_s;
    if (prev_wake > 0) {
      const double error_us = std::abs(static_cast<double>(wake - prev_wake - period_ns)) * 1e-3;
      period_error.Add(error_us);
      window_error.Add(error_us);
    }
    prev_wake = wake;

    // 1. answers in, through the impairment
    link_->Poll([&](const Answer& a, int64_t arrived_ns) { answers_in.Push(arrived_ns, a); });
    answers_in.Deliver(wake, accept);

    // 2. the device, and its pose out
    DeviceSample sample = device_->Read(t);
    if (!sample.position.allFinite()) {
      ++device_nonfinite;
      model.FlagNonFinite(wake);
      sample.position = x_prev.allFinite() ? x_prev : Vec3::Zero();
    }
    const Vec3& x = sample.position;
    passivity.Observe(x);
    const Vec3 v = x_prev.allFinite() ? Vec3((x - x_prev) / dt) : Vec3::Zero();
    x_prev = x;
    const bool moved = !x_sent.allFinite() || (x - x_sent).norm() > options_.deadband_m;
    if (options_.deadband_m <= 0.0 || moved ||
        static_cast<double>(wake - last_sent_ns) * 1e-9 >= options_.keepalive_s) {
      history.Add(seq, x, wake);
      poses_out.Push(wake, {seq, sample});
      ++seq;
      x_sent = x;
      last_sent_ns = wake;
    }
    poses_out.Deliver(wake, [&](const std::pair<int64_t, DeviceSample>& p, int64_t) {
      link_->SendPose(p.first, p.second);
    });

    // 3. the force: local model, limits, then the passivity controller's damping (last, so
    // that the rate limit cannot hold back the energy it removes) within the force limit
    const Vec3 limited = limiter.Apply(model.Force(x, wake), dt);
    Vec3 f = passivity.Control(limited, v, period_s);
    if (f.norm() > max_force) f *= max_force / f.norm();
    device_->Write(f);
    passivity.Commit(f);

    // 4. figures, log, report
    const double age = model.age_s(wake);
    if (std::isfinite(age)) model_age.Add(age * 1e3);
    s.peak_force_n = std::max(s.peak_force_n, f.norm());
    if (options_.log != nullptr) {
      WriteLogLine(options_.log, t, x, f, limited,
                   model.has_answer() ? model.newest().force : Vec3::Zero(), age * 1e3, dt * 1e6,
                   model.gain(), passivity.energy_j(),
                   model.nonfinite() + limiter.nonfinite() + device_nonfinite);
    }
    ++window_periods;
    if (options_.on_report && wake >= next_report) {
      LoopReport r;
      r.t_s = t;
      r.rate_hz =
          static_cast<double>(window_periods) * 1e9 / static_cast<double>(wake - window_start);
      r.period_error_p99_us = window_error.Quantile(0.99);
      r.round_trip_p50_us = window_trip.Quantile(0.5);
      r.model_age_ms = age * 1e3;
      r.force_n = f.norm();
      r.gain = model.gain();
      r.misses = pacer.misses();
      options_.on_report(r);
      window_error.Clear();
      window_trip.Clear();
      window_periods = 0;
      window_start = wake;
      next_report = wake + static_cast<int64_t>(options_.report_period_s * 1e9);
    }
    pacer.Advance(MonotonicNanos());
  }

  s.duration_s = static_cast<double>(prev_wake - start) * 1e-9;
  s.periods = pacer.periods() - 1;  // the last Wait only ended the loop
  s.achieved_rate_hz = s.duration_s > 0.0 ? static_cast<double>(s.periods - 1) / s.duration_s : 0.0;
  s.period_error_p50_us = period_error.Quantile(0.5);
  s.period_error_p99_us = period_error.Quantile(0.99);
  s.period_error_max_us = period_error.Max();
  s.misses = pacer.misses();
  s.late_wakeups = pacer.late_wakeups();
  s.resyncs = pacer.resyncs();
  s.round_trips = static_cast<int64_t>(round_trip.size());
  s.round_trip_p50_us = round_trip.Quantile(0.5);
  s.round_trip_p99_us = round_trip.Quantile(0.99);
  s.model_age_p50_ms = model_age.Quantile(0.5);
  s.model_age_p99_ms = model_age.Quantile(0.99);
  s.poses_sent = poses_out.pushed();
  s.poses_lost = poses_out.lost();
  s.answers_accepted = model.accepted();
  s.answers_out_of_order = model.out_of_order();
  // every step of the server answers once: the steps between the first and last heard that
  // never arrived (on the network or in the impairment) are lost
  const int64_t heard = s.answers_received;
  s.answers_lost = last_step >= first_step && first_step >= 0
                       ? std::max<int64_t>(0, last_step - first_step + 1 - heard)
                       : 0;
  s.link_rejected = link_->rejected();
  s.force_clamped = limiter.clamped();
  s.rate_limited = limiter.rate_limited();
  s.stiffness_capped = model.stiffness_capped();
  s.nonfinite_events = model.nonfinite() + limiter.nonfinite() + device_nonfinite;
  s.fade_events = model.fade_events();
  s.energy_j = passivity.energy_j();
  s.min_energy_j = passivity.min_energy_j();
  s.dissipated_j = passivity.dissipated_j();
  s.passivity_activations = passivity.activations();
  return s;
}

}  // namespace viscera::haptic
