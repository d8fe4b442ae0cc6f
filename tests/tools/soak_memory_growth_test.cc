// The soak's memory verdict (tools/soak/memory_growth.h) on synthetic RSS series shaped like the
// measured ones (docs/reliability.md): the server grows in steps at its first blow-up cycles, then
// stays flat; a leak grows by the same amount every cycle. And the soak's records check
// (tools/soak/soak_records.h).
#include "tools/soak/memory_growth.h"

#include <gtest/gtest.h>

#include <functional>
#include <vector>

#include "tools/soak/soak_cadence.h"
#include "tools/soak/soak_records.h"

namespace viscera::soak {
namespace {

using Outcome = GrowthVerdict::Outcome;

// `cycles` samples, `per_second` cycles a second, RSS in kB by cycle number.
std::vector<RssSample> Series(int64_t cycles, double per_second,
                              const std::function<int64_t(int64_t)>& rss_kb) {
  std::vector<RssSample> series;
  for (int64_t c = 1; c <= cycles; ++c) series.push_back({c, c / per_second, rss_kb(c)});
  return series;
}

// Idle 100 MB, then a step at each of the first six blow-up cycles (3, 13, ..., 53) and 2 MB more
// on the cycle after, as measured under load (the first step the largest): 100 MB in all. Flat
// from cycle 54.
int64_t WarmingUp(int64_t cycle) {
  const int64_t steps_mb[] = {50, 8, 8, 6, 6, 10};
  int64_t kb = 100 * 1024;
  for (int64_t i = 0, c = 3; i < 6 && c <= cycle; ++i, c += kCadencePeriod) {
    kb += steps_mb[i] * 1024 + (cycle > c ? 2 * 1024 : 0);
  }
  return kb;
}

// A few hundred kB of noise, repeating every 7 cycles.
int64_t Noise(int64_t cycle) { return (cycle % 7) * 60; }

constexpr int64_t kWarmCycles = 6 * kCadencePeriod;  // six blow-ups, as the series above needs
constexpr double kBoundMb = 16.0;

GrowthPolicy Policy(double run_seconds) {
  return {.warm_cycles = kWarmCycles,
          .warm_seconds = run_seconds / 4,
          .judged_cycles = 2 * kCadencePeriod,
          .bound_mb = kBoundMb};
}

TEST(SoakCadence, EveryKindRunsInEachPeriod) {
  for (int64_t first = 1; first <= 100; ++first) {
    int frames = 0, hostile = 0, blowups = 0;
    for (int64_t c = first; c < first + kCadencePeriod; ++c) {
      frames += FramesOn(c) ? 1 : 0;
      hostile += HostileScenes(c) ? 1 : 0;
      blowups += BlowUp(c) ? 1 : 0;
      EXPECT_EQ(FramesOn(c), FramesOn(c + kCadencePeriod));
      EXPECT_EQ(HostileScenes(c), HostileScenes(c + kCadencePeriod));
      EXPECT_EQ(BlowUp(c), BlowUp(c + kCadencePeriod));
    }
    EXPECT_EQ(frames, 5);
    EXPECT_EQ(hostile, 2);
    EXPECT_EQ(blowups, 1);
  }
}

TEST(SoakMemoryGrowth, FlatAfterWarmUpPasses) {
  // a quiet machine: 2.5 cycles a second, 40 s
  const auto series = Series(100, 2.5, [](int64_t c) { return WarmingUp(c) + Noise(c); });
  const GrowthVerdict v = JudgeGrowth(series, Policy(40));
  EXPECT_EQ(v.outcome, Outcome::kFlat) << v.message;
  EXPECT_EQ(v.baseline.cycle, kWarmCycles);  // 24 s: the first quarter (10 s) was over before
  EXPECT_EQ(v.last.cycle, 100);
  EXPECT_EQ(v.judged_cycles, 40);
  EXPECT_DOUBLE_EQ(v.growth_mb, (Noise(100) - Noise(kWarmCycles)) / 1024.0);
}

TEST(SoakMemoryGrowth, WarmUpGrowthBeforeTheBaselinePassesOnALoadedMachine) {
  // a loaded machine: 1.1 cycles a second, so the first quarter of 40 s ends at cycle 11 with 48
  // of the warm-up's 100 MB still to come; the run went on to cycle 80
  const auto series = Series(80, 1.1, [](int64_t c) { return WarmingUp(c) + Noise(c); });
  const GrowthVerdict v = JudgeGrowth(series, Policy(40));
  EXPECT_EQ(v.outcome, Outcome::kFlat) << v.message;
  EXPECT_EQ(v.baseline.cycle, kWarmCycles);
  // the safeguard: a baseline at the first quarter of the time (the rule before) judges the
  // warm-up's later steps as growth and fails
  GrowthPolicy by_time = Policy(40);
  by_time.warm_cycles = 0;
  const GrowthVerdict old = JudgeGrowth(series, by_time);
  EXPECT_EQ(old.baseline.cycle, 11);
  EXPECT_EQ(old.outcome, Outcome::kGrew) << old.message;
  EXPECT_NEAR(old.growth_mb, 48.0, 0.5);
}

TEST(SoakMemoryGrowth, TheFirstQuarterStillHoldsTheBaselineBackOnAFastMachine) {
  // 10 cycles a second: cycle 60 at 6 s, the first quarter ends at 10 s (cycle 100)
  const auto series = Series(400, 10.0, [](int64_t c) { return WarmingUp(c) + Noise(c); });
  const GrowthVerdict v = JudgeGrowth(series, Policy(40));
  EXPECT_EQ(v.baseline.cycle, 100);
  EXPECT_EQ(v.outcome, Outcome::kFlat) << v.message;
}

TEST(SoakMemoryGrowth, SteadyGrowthAfterWarmUpFails) {
  // a MB a cycle after warm-up (one leaked per session): 40 cycles judged make 40 MB
  const auto leak = [](int64_t c) {
    return WarmingUp(c) + Noise(c) + (c > kWarmCycles ? (c - kWarmCycles) * 1024 : 0);
  };
  const GrowthVerdict v = JudgeGrowth(Series(100, 2.5, leak), Policy(40));
  EXPECT_EQ(v.outcome, Outcome::kGrew) << v.message;
  EXPECT_NEAR(v.growth_mb, 40.0, 0.5);
  // the smallest leak the shortest judged window (20 cycles) is sure to catch: bound / 20 cycles
  const auto small_leak = [](int64_t c) {
    return WarmingUp(c) + (c > kWarmCycles ? (c - kWarmCycles) * 820 : 0);
  };
  EXPECT_EQ(JudgeGrowth(Series(80, 2.5, small_leak), Policy(40)).outcome, Outcome::kGrew);
  const auto smaller_leak = [](int64_t c) {
    return WarmingUp(c) + (c > kWarmCycles ? (c - kWarmCycles) * 810 : 0);
  };
  EXPECT_EQ(JudgeGrowth(Series(80, 2.5, smaller_leak), Policy(40)).outcome, Outcome::kFlat);
}

TEST(SoakMemoryGrowth, TheBoundIsInclusive) {
  const auto at_bound = [](int64_t c) {
    return c < 70 ? int64_t{100 * 1024} : int64_t{116 * 1024};
  };
  EXPECT_EQ(JudgeGrowth(Series(90, 1.0, at_bound), Policy(40)).outcome, Outcome::kFlat);
  const auto past_bound = [](int64_t c) {
    return c < 70 ? int64_t{100 * 1024} : int64_t{116 * 1024 + 1};
  };
  EXPECT_EQ(JudgeGrowth(Series(90, 1.0, past_bound), Policy(40)).outcome, Outcome::kGrew);
}

TEST(SoakMemoryGrowth, NoBaselineBeforeTheWarmCyclesGivesNoVerdict) {
  // a loaded machine's 40 s ended at cycle 45
  const GrowthVerdict v = JudgeGrowth(Series(45, 1.1, WarmingUp), Policy(40));
  EXPECT_EQ(v.outcome, Outcome::kTooShort);
  EXPECT_EQ(v.baseline.cycle, 0);
  EXPECT_EQ(v.message,
            "too short to judge: no baseline yet (it needs cycle >= 60 and 10.0 s; the run reached "
            "cycle 45 at 40.9 s)");
  EXPECT_EQ(JudgeGrowth({}, Policy(40)).outcome, Outcome::kTooShort);
}

TEST(SoakMemoryGrowth, TooFewCyclesAfterTheBaselineGiveNoVerdict) {
  const GrowthVerdict v = JudgeGrowth(Series(70, 1.1, WarmingUp), Policy(40));
  EXPECT_EQ(v.outcome, Outcome::kTooShort);
  EXPECT_EQ(v.baseline.cycle, kWarmCycles);
  EXPECT_EQ(v.judged_cycles, 10);
  EXPECT_EQ(v.message, "too short to judge: 10 cycles after the baseline (cycle 60), 20 needed");
  // one cycle short of a verdict, then a verdict
  EXPECT_EQ(JudgeGrowth(Series(79, 1.1, WarmingUp), Policy(40)).outcome, Outcome::kTooShort);
  EXPECT_EQ(JudgeGrowth(Series(80, 1.1, WarmingUp), Policy(40)).outcome, Outcome::kFlat);
}

}  // namespace
}  // namespace viscera::soak

namespace viscera::soak {
namespace {

// The records check (soak_records.h): a create whose reply was lost may or may not have made a
// session; every answered one must have its record.
TEST(SoakRecords, OneRecordPerAnsweredSessionAndAtMostOneMorePerUnansweredCreate) {
  EXPECT_TRUE(RecordsAccountedFor(50, 50, 0));
  EXPECT_FALSE(RecordsAccountedFor(51, 50, 0));  // a record nobody asked for
  EXPECT_TRUE(RecordsAccountedFor(51, 50, 1));   // a loaded run's case: a lost reply
  EXPECT_TRUE(RecordsAccountedFor(50, 50, 1));   // the create itself was lost
  EXPECT_FALSE(RecordsAccountedFor(52, 50, 1));
  EXPECT_FALSE(RecordsAccountedFor(49, 50, 3));  // an answered session without its record
}

}  // namespace
}  // namespace viscera::soak
