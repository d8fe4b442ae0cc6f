#include "session/loop_stats.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace viscera::session {

LoopStats::LoopStats(int capacity) : capacity_(capacity) {
  VISCERA_DEMAND(capacity >= 1);
  cost_us_.resize(static_cast<size_t>(capacity));
  jitter_us_.resize(static_cast<size_t>(capacity));
  wall_us_.resize(static_cast<size_t>(capacity));
  scratch_.resize(static_cast<size_t>(capacity));
}

void LoopStats::RecordStep(int64_t cost_ns, int64_t lateness_ns) {
  const auto slot = static_cast<size_t>(count_ % capacity_);
  cost_us_[slot] = static_cast<double>(cost_ns) * 1e-3;
  jitter_us_[slot] = static_cast<double>(std::max<int64_t>(lateness_ns, 0)) * 1e-3;
  ++count_;
}

void LoopStats::RecordWall(int64_t ns) {
  wall_max_ns_ = std::max(wall_max_ns_, ns);
  wall_us_[static_cast<size_t>(wall_count_ % capacity_)] = static_cast<double>(ns) * 1e-3;
  ++wall_count_;
}

LoopSummary LoopStats::Summarize(int64_t elapsed_ns) {
  LoopSummary s;
  const int n = static_cast<int>(std::min<int64_t>(count_, capacity_));
  if (elapsed_ns > 0) s.achieved_rate_hz = static_cast<double>(count_) * 1e9 / elapsed_ns;
  std::copy_n(cost_us_.begin(), n, scratch_.begin());
  s.step_cost_p50_us = static_cast<float>(Quantile(scratch_.data(), n, 0.5));
  s.step_cost_p99_us = static_cast<float>(Quantile(scratch_.data(), n, 0.99));
  std::copy_n(jitter_us_.begin(), n, scratch_.begin());
  s.jitter_p99_us = static_cast<float>(Quantile(scratch_.data(), n, 0.99));
  s.wall_max_us = static_cast<float>(static_cast<double>(wall_max_ns_) * 1e-3);
  const int walls = static_cast<int>(std::min<int64_t>(wall_count_, capacity_));
  std::copy_n(wall_us_.begin(), walls, scratch_.begin());
  s.wall_p90_us = static_cast<float>(Quantile(scratch_.data(), walls, kSlackQuantile));
  wall_max_ns_ = 0;
  wall_count_ = 0;
  count_ = 0;
  return s;
}

double StepSlack(const LoopSummary& summary, double rate_hz) {
  return rate_hz > 0.0 ? 1.0 - summary.wall_p90_us * 1e-6 * rate_hz : 1.0;
}

}  // namespace viscera::session
