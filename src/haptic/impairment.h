#pragma once
/// Network impairment for tests and demos: each message is lost with probability `loss`, or
/// delivered `delay` later plus a jitter drawn uniformly from [-jitter, +jitter] (never
/// before it was sent). Jitter larger than the gap between messages reorders them, as a real
/// network does. Seeded: the same seed gives the same losses and delays, so a test run can
/// be repeated.
///
/// Threading: one thread (the device loop's). Allocates while its queue grows, then no more.
#include <algorithm>
#include <cstdint>
#include <functional>
#include <queue>
#include <vector>

#include "common/check.h"

namespace viscera::haptic {

struct ImpairmentOptions {
  double delay_s = 0.0;   ///< one way (s), >= 0
  double jitter_s = 0.0;  ///< +- (s), >= 0
  double loss = 0.0;      ///< fraction of messages lost, 0..1
  uint64_t seed = 1;

  bool active() const { return delay_s > 0.0 || jitter_s > 0.0 || loss > 0.0; }
  /// @throws InputError for a negative delay or jitter, or a loss outside 0..1.
  void Validate() const {
    ThrowUnless(delay_s >= 0.0 && jitter_s >= 0.0, "impairment: delay ", delay_s * 1e3,
                " ms and jitter ", jitter_s * 1e3, " ms must be >= 0");
    ThrowUnless(loss >= 0.0 && loss <= 1.0, "impairment: loss must be within 0..1, got ", loss);
  }
};

/// SplitMix64: small, fast, and the same sequence on every platform.
class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}
  uint64_t Next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1).
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }

 private:
  uint64_t state_;
};

/// One direction of an impaired link, carrying messages of type T.
template <typename T>
class ImpairedChannel {
 public:
  /// @param stream separates the random streams of the two directions of one seed.
  ImpairedChannel(const ImpairmentOptions& options, uint64_t stream)
      : options_(options), rng_(options.seed * 0x100000001B3ull + stream) {
    options_.Validate();
  }

  /// A message sent at `now_ns` (monotonic): dropped, or queued for its delivery time.
  void Push(int64_t now_ns, const T& message) {
    ++pushed_;
    if (options_.loss > 0.0 && rng_.Uniform() < options_.loss) {
      ++lost_;
      return;
    }
    double delay = options_.delay_s;
    if (options_.jitter_s > 0.0) delay += options_.jitter_s * (2.0 * rng_.Uniform() - 1.0);
    const int64_t due = now_ns + static_cast<int64_t>(std::max(0.0, delay) * 1e9);
    queue_.push(Item{due, order_++, message});
  }

  /// Hands every message due by `now_ns` to `deliver` with its delivery time, in order of
  /// delivery time.
  void Deliver(int64_t now_ns, const std::function<void(const T&, int64_t due_ns)>& deliver) {
    while (!queue_.empty() && queue_.top().due_ns <= now_ns) {
      const Item item = queue_.top();
      queue_.pop();
      deliver(item.message, item.due_ns);
    }
  }

  int64_t pushed() const { return pushed_; }
  int64_t lost() const { return lost_; }
  size_t queued() const { return queue_.size(); }

 private:
  struct Item {
    int64_t due_ns;
    int64_t order;  // equal due times keep their sending order
    T message;
    bool operator>(const Item& o) const {
      return due_ns != o.due_ns ? due_ns > o.due_ns : order > o.order;
    }
  };
  ImpairmentOptions options_;
  SplitMix64 rng_;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue_;
  int64_t order_ = 0, pushed_ = 0, lost_ = 0;
};

}  // namespace viscera::haptic
