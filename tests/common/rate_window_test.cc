#include "common/rate_window.h"

#include <gtest/gtest.h>

namespace viscera {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(RateWindow, CountsPerSecondOverAboutTheLastSecond) {
  RateWindow w;
  EXPECT_EQ(w.Rate(), 0.0);
  w.Add(0, 0);
  EXPECT_FALSE(w.ready());
  EXPECT_EQ(w.Rate(), 0.0);
  // 100 per second, sampled every 250 ms for 3 s
  for (int64_t t = 250; t <= 3000; t += 250) w.Add(t * kMs, t / 10);
  EXPECT_TRUE(w.ready());
  EXPECT_DOUBLE_EQ(w.Rate(), 100.0);
  // then nothing for 1.5 s: the window has forgotten the busy time
  w.Add(3750 * kMs, 300);
  w.Add(4500 * kMs, 300);
  EXPECT_DOUBLE_EQ(w.Rate(), 0.0);
}

TEST(RateWindow, OneStallOfAFewPeriodsDoesNotReadAsASlowLoop) {
  RateWindow w;
  int64_t count = 0;
  for (int64_t t = 0; t <= 2000; t += 250) {
    count += t == 1750 ? 0 : 25;  // 100 per second, but nothing in one stalled period
    w.Add(t * kMs, count);
  }
  // 100/s except one 250 ms period: over the last second 75 of 100 counts
  EXPECT_NEAR(w.Rate(), 75.0, 1e-9);
  w.Clear();
  EXPECT_FALSE(w.ready());
}

}  // namespace
}  // namespace viscera
