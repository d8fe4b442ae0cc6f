#include "common/pacer.h"

#include <gtest/gtest.h>

#include <vector>

#include "common/check.h"
#include "common/clock.h"

namespace viscera {
namespace {

constexpr int64_t kUs = 1'000;
constexpr int64_t kMs = 1'000'000;

// A fake monotonic clock: each sleep overshoots by the next of `oversleep` (then 0), each
// read costs `read_cost` ns (so a spin makes progress).
struct FakeClock {
  int64_t t = 0;
  int64_t read_cost = 100;
  std::vector<int64_t> oversleep;
  size_t next = 0;
  int sleeps = 0;
  PacerClock Clock() {
    return {[this] { return t += read_cost; },
            [this](int64_t until) {
              ++sleeps;
              const int64_t over = next < oversleep.size() ? oversleep[next++] : 0;
              t = std::max(t, until + over);
            }};
  }
};

TEST(Pacer, SleepsUntilTheSpinMarginThenSpinsToTheDeadline) {
  FakeClock c;
  Pacer pacer({.period_ns = kMs, .spin_ns = 200 * kUs, .late_ns = 50 * kUs}, c.Clock());
  pacer.Start(0);
  for (int k = 0; k < 10; ++k) {
    const int64_t wake = pacer.Wait();
    // never before the deadline, and within one clock read after it
    EXPECT_GE(wake, k * kMs);
    EXPECT_LT(wake, k * kMs + 2 * c.read_cost);
    EXPECT_FALSE(pacer.Advance(wake + 300 * kUs));
  }
  EXPECT_EQ(c.sleeps, 9);  // the first deadline (0) was already due
  EXPECT_EQ(pacer.periods(), 10);
  EXPECT_EQ(pacer.late_wakeups(), 0);
  EXPECT_EQ(pacer.misses(), 0);
}

TEST(Pacer, TheSpinAbsorbsOversleepShorterThanItsMargin) {
  FakeClock spin, sleep_only;
  // wake-ups 150 us late: the spin margin (200 us) hides them; sleeping only does not
  spin.oversleep = sleep_only.oversleep = std::vector<int64_t>(20, 150 * kUs);
  Pacer a({.period_ns = kMs, .spin_ns = 200 * kUs, .late_ns = 50 * kUs}, spin.Clock());
  Pacer b({.period_ns = kMs, .spin_ns = 0, .late_ns = 50 * kUs}, sleep_only.Clock());
  a.Start(kMs);
  b.Start(kMs);
  for (int k = 0; k < 20; ++k) {
    a.Advance(a.Wait());
    b.Advance(b.Wait());
  }
  EXPECT_EQ(a.late_wakeups(), 0);
  EXPECT_EQ(b.late_wakeups(), 20);
  EXPECT_GE(b.last_lateness_ns(), 150 * kUs);
}

TEST(Pacer, CountsLateWakeupsMissesAndResyncsExactly) {
  FakeClock c;
  // sleeps end after their target (200 us before the deadline) by: 0, 260 us (60 us late), 0,
  // and 5 ms (a stall); period 3 sleeps not at all (period 2 ran long)
  c.oversleep = {0, 260 * kUs, 0, 5 * kMs};
  Pacer pacer({.period_ns = kMs, .spin_ns = 200 * kUs, .late_ns = 50 * kUs}, c.Clock());
  pacer.Start(kMs);
  std::vector<int64_t> deadlines;
  for (int k = 0; k < 7; ++k) {
    deadlines.push_back(pacer.deadline());
    const int64_t wake = pacer.Wait();
    // the work takes 100 us, but period 2's runs long: it ends after period 3's deadline
    c.t = k == 2 ? wake + 1500 * kUs : wake + 100 * kUs;
    pacer.Advance(c.t);
  }
  EXPECT_EQ(pacer.late_wakeups(), 3);  // 60 us, period 3 (500 us), the stall
  EXPECT_EQ(pacer.misses(), 2);        // the long period and the stall
  EXPECT_EQ(pacer.resyncs(), 1);       // after the stall it starts again, no burst
  EXPECT_EQ(c.sleeps, 5);
  EXPECT_EQ(deadlines[1], 2 * kMs);
  EXPECT_EQ(deadlines[3], 4 * kMs);
  EXPECT_EQ(deadlines[4], 5 * kMs);
  EXPECT_GT(deadlines[5], 9 * kMs);  // restarted from the end of the stalled period
  EXPECT_EQ(deadlines[6], deadlines[5] + kMs);
}

TEST(Pacer, RejectsBadOptions) {
  EXPECT_THROW(Pacer({.period_ns = 0}), InputError);
  EXPECT_THROW(Pacer({.period_ns = kMs, .spin_ns = -1}), InputError);
  EXPECT_THROW(Pacer({.period_ns = kMs, .spin_ns = 0, .late_ns = -1}), InputError);
}

TEST(Pacer, OnTheRealClockNeverWakesBeforeItsDeadline) {
  Pacer pacer({.period_ns = kMs, .spin_ns = 100 * kUs});
  pacer.Start();
  for (int k = 0; k < 50; ++k) {
    const int64_t deadline = pacer.deadline();
    EXPECT_GE(pacer.Wait(), deadline);
    EXPECT_GE(MonotonicNanos(), deadline);
    pacer.Advance(MonotonicNanos());
  }
  EXPECT_EQ(pacer.periods(), 50);
}

}  // namespace
}  // namespace viscera
