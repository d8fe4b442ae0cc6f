#pragma once
/// LoopStats: timing of a fixed-rate loop over a status period: step cost and wake-up
/// jitter percentiles, achieved rate, deadline misses. Fixed-size buffers: recording is
/// allocation-free; Summarize sorts a preallocated copy.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "common/quantile.h"

namespace viscera::session {

struct LoopSummary {
  double achieved_rate_hz = 0.0;  ///< steps over wall time since the previous summary (Hz)
  float step_cost_p50_us = 0.0f;  ///< CPU time per step (µs)
  float step_cost_p99_us = 0.0f;
  float jitter_p99_us = 0.0f;  ///< wake-up lateness (µs)
  float wall_max_us = 0.0f;    ///< longest scheduled start -> step done (µs)
  float wall_p90_us = 0.0f;    ///< 90th percentile of the same (µs): what the step slack reads
};

/// The quantile of the steps' wall times that the step slack reads. A status period holds 25
/// steps at 100 Hz: the 90th percentile passes over its two longest, which a machine busy with
/// other work delays for reasons no frame stream causes, while a stream that starves the
/// mechanics lengthens far more of them than one in ten.
inline constexpr double kSlackQuantile = 0.9;

/// The mechanics' step slack over a status period: 1 - the `kSlackQuantile` step wall time /
/// the step period of a loop at `rate_hz`; 1 when the rate is unknown or no step was timed.
double StepSlack(const LoopSummary& summary, double rate_hz);

class LoopStats {
 public:
  /// Keeps at most `capacity` samples per period (older ones are overwritten).
  explicit LoopStats(int capacity = 4096);

  /// One step: its CPU cost (ns) and how late the thread woke for it (ns, >= 0).
  void RecordStep(int64_t cost_ns, int64_t lateness_ns);
  /// A step that ended after its deadline.
  void RecordMiss() { ++deadline_misses_; }
  /// Wall time from a step's scheduled start to its end (ns).
  void RecordWall(int64_t ns);

  /// Summary of the steps since the previous call over `elapsed_ns` of wall time; starts a
  /// new period.
  LoopSummary Summarize(int64_t elapsed_ns);

  int64_t deadline_misses() const { return deadline_misses_; }

 private:
  int capacity_;
  std::vector<double> cost_us_, jitter_us_, wall_us_, scratch_;
  int64_t count_ = 0;       // steps this period
  int64_t wall_count_ = 0;  // wall times this period
  int64_t deadline_misses_ = 0;
  int64_t wall_max_ns_ = 0;
};

}  // namespace viscera::session
