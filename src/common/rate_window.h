#pragma once
/// RateWindow: events per second over about the last second, from samples of a running
/// count (steps taken, frames sent) taken now and then. Over a second rather than one
/// sampling period, so that one stall of a few periods does not read as a slow loop.
#include <cstdint>
#include <deque>
#include <utility>

namespace viscera {

class RateWindow {
 public:
  /// Adds the running `count` at monotonic time `now_ns` (not before the previous sample);
  /// forgets samples older than a second, keeping the newest of those as the window's start.
  void Add(int64_t now_ns, int64_t count) {
    samples_.emplace_back(now_ns, count);
    while (samples_.size() > 2 && samples_[1].first <= now_ns - 1'000'000'000) samples_.pop_front();
  }
  /// Counts per second between the window's first and last samples; 0 with fewer than two
  /// samples or no time between them.
  double Rate() const {
    if (samples_.size() < 2 || samples_.back().first <= samples_.front().first) return 0.0;
    return static_cast<double>(samples_.back().second - samples_.front().second) * 1e9 /
           static_cast<double>(samples_.back().first - samples_.front().first);
  }
  bool ready() const { return samples_.size() >= 2; }
  void Clear() { samples_.clear(); }

 private:
  std::deque<std::pair<int64_t, int64_t>> samples_;  // (monotonic ns, running count)
};

}  // namespace viscera
