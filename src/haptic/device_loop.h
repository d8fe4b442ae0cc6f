#pragma once
/// DeviceLoop: the haptic device loop. Every period (1 kHz by default, absolute deadlines,
/// common/pacer.h) it
///   1. takes the force answers that arrived (through the network impairment, if any) into the
///      local model: stale and out-of-order ones dropped, non-finite ones counted;
///   2. reads the device and publishes its pose (every period, or past a deadband);
///   3. renders F = g(age) [F_s - K (x_now - x_answered)] (local_model.h), through the force
///      and force-rate limits (force_limiter.h), adds the passivity controller's damping
///      (passivity.h) and, within the force limit, writes it to the device;
///   4. keeps its figures (period error, misses, round trip, model age) and, when asked, a log
///      line and a live report.
/// docs/haptics.md explains the loop and its choices.
///
/// Threading: Run() runs the loop on the calling thread, which must own the link's bus.
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>

#include "haptic/device.h"
#include "haptic/force_link.h"
#include "haptic/impairment.h"
#include "haptic/local_model.h"

namespace viscera::haptic {

/// What the live report shows (about every report_period_s).
struct LoopReport {
  double t_s = 0.0;                  ///< since the loop started
  double rate_hz = 0.0;              ///< periods per second over the report period
  double period_error_p99_us = 0.0;  ///< over the report period
  double round_trip_p50_us = 0.0;    ///< over the report period (0 when none)
  double model_age_ms = 0.0;         ///< now (inf before the first answer)
  double force_n = 0.0;              ///< |F| sent now
  double gain = 0.0;                 ///< stale-fade gain now
  int64_t misses = 0;                ///< so far
};

struct DeviceLoopOptions {
  double rate_hz = 1000.0;    ///< device loop rate (Hz), > 0
  double seconds = 0.0;       ///< run time (s); 0: the device's duration, or until stop
  int64_t spin_ns = -1;       ///< pacer spin margin (ns); < 0: AutoSpinNs (common/pacer.h)
  int realtime_priority = 0;  ///< > 0: SCHED_FIFO at this priority (reported when refused)
  double deadband_m = 0.0;    ///< publish when moved more than this (m); 0: every period
  double keepalive_s = 0.02;  ///< with a deadband: publish at least this often (s)
  /// Local model; its max_stiffness_n_m is lowered to the device's limit and the Colgate bound.
  LocalModelOptions model;
  double max_force_n = 0.0;           ///< force limit (N); 0 or above the device's: the device's
  double max_force_rate_n_s = 200.0;  ///< force-rate limit (N/s)
  bool passivity = true;              ///< false: observe only (for comparison)
  ImpairmentOptions impairment;       ///< applied to poses out and answers in
  std::FILE* log = nullptr;           ///< JSON line per period when set (docs/haptics.md)
  double report_period_s = 0.5;
  std::function<void(const LoopReport&)> on_report;  ///< live report, when set
  const std::atomic<bool>* stop = nullptr;           ///< ends the loop when it turns true
};

struct LoopSummary {
  std::string device;
  double duration_s = 0.0;
  double rate_hz = 0.0, achieved_rate_hz = 0.0;
  int64_t periods = 0;
  double period_error_p50_us = 0.0, period_error_p99_us = 0.0, period_error_max_us = 0.0;
  int64_t misses = 0, late_wakeups = 0, resyncs = 0;
  std::string realtime;  ///< "off", "SCHED_FIFO <prio>", or why it was refused
  double round_trip_p50_us = 0.0, round_trip_p99_us = 0.0;
  int64_t round_trips = 0;
  double model_age_p50_ms = 0.0, model_age_p99_ms = 0.0;
  int64_t poses_sent = 0, poses_lost = 0;  ///< lost: by the impairment
  int64_t answers_received = 0;            ///< delivered to the model
  int64_t answers_accepted = 0, answers_out_of_order = 0, answers_unmatched = 0;
  int64_t answers_lost = 0;  ///< steps of the server never heard
  int64_t link_rejected = 0;
  double peak_force_n = 0.0;
  double max_force_n = 0.0, max_force_rate_n_s = 0.0, max_stiffness_n_m = 0.0;
  int64_t force_clamped = 0, rate_limited = 0, stiffness_capped = 0;
  int64_t nonfinite_events = 0;  ///< answers, device readings or forces with NaN or inf
  int64_t fade_events = 0;
  bool passivity = true;
  double energy_j = 0.0, min_energy_j = 0.0, dissipated_j = 0.0;
  int64_t passivity_activations = 0;
};

class DeviceLoop {
 public:
  /// @pre device and link outlive the loop.
  /// @throws InputError for bad options (rate, limits, impairment, model).
  DeviceLoop(Device* device, ForceLink* link, DeviceLoopOptions options);

  /// Runs until `seconds`, the device's duration, or `stop`.
  LoopSummary Run();

 private:
  Device* device_;
  ForceLink* link_;
  DeviceLoopOptions options_;
};

}  // namespace viscera::haptic
