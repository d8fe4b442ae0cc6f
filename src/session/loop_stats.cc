#include "session/loop_stats.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace viscera::session {

LoopStats::LoopStats(int capacity) : capacity_(capacity) {
  VISCERA_DEMAND(capacity >= 1);
  cost_us_.resize(static_cast<size_t>(capacity));
  jitter_us_.resize(static_cast<size_t>(capacity));
  scratch_.resize(static_cast<size_t>(capacity));
}

void LoopStats::RecordStep(int64_t cost_ns, int64_t lateness_ns) {
  const auto slot = static_cast<size_t>(count_ % capacity_);
  cost_us_[slot] = static_cast<double>(cost_ns) * 1e-3;
  jitter_us_[slot] = static_cast<double>(std::max<int64_t>(lateness_ns, 0)) * 1e-3;
  ++count_;
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
  wall_max_ns_ = 0;
  count_ = 0;
  return s;
}

}  // namespace viscera::session
