#include "session/loop_stats.h"

#include <gtest/gtest.h>

#include <vector>

namespace viscera::session {
namespace {

TEST(Quantile, NearestRank) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);
  EXPECT_DOUBLE_EQ(Quantile(v.data(), 100, 0.5), 50.0);
  EXPECT_DOUBLE_EQ(Quantile(v.data(), 100, 0.99), 99.0);
  EXPECT_DOUBLE_EQ(Quantile(v.data(), 100, 1.0), 100.0);
  EXPECT_DOUBLE_EQ(Quantile(v.data(), 0, 0.5), 0.0);
}

TEST(LoopStats, SummarizesOnePeriodAtATime) {
  LoopStats stats(1000);
  for (int i = 1; i <= 100; ++i) stats.RecordStep(/*cost_ns=*/i * 1000, /*lateness_ns=*/i * 10);
  stats.RecordMiss();
  const LoopSummary a = stats.Summarize(/*elapsed_ns=*/1'000'000'000);
  EXPECT_DOUBLE_EQ(a.achieved_rate_hz, 100.0);
  EXPECT_FLOAT_EQ(a.step_cost_p50_us, 50.0f);
  EXPECT_FLOAT_EQ(a.step_cost_p99_us, 99.0f);
  EXPECT_FLOAT_EQ(a.jitter_p99_us, 0.99f);
  EXPECT_EQ(stats.deadline_misses(), 1);
  const LoopSummary b = stats.Summarize(500'000'000);
  EXPECT_DOUBLE_EQ(b.achieved_rate_hz, 0.0);  // nothing since
  EXPECT_EQ(stats.deadline_misses(), 1);      // misses are counted for the session's life
}

TEST(LoopStats, StepSlackReadsTheNinetiethPercentileWallTime) {
  LoopStats stats(1000);
  // a status period at 100 Hz: 20 steps of 2 ms wall time, 3 of 5 ms, 2 of 9 ms
  for (int i = 0; i < 2; ++i) stats.RecordWall(9'000'000);
  for (int i = 0; i < 3; ++i) stats.RecordWall(5'000'000);
  for (int i = 0; i < 20; ++i) stats.RecordWall(2'000'000);
  const LoopSummary a = stats.Summarize(250'000'000);
  EXPECT_FLOAT_EQ(a.wall_max_us, 9000.0f);
  EXPECT_FLOAT_EQ(a.wall_p90_us, 5000.0f);  // the 23rd shortest of 25
  EXPECT_NEAR(StepSlack(a, 100.0), 0.5, 1e-6);
  for (int i = 0; i < 23; ++i) stats.RecordWall(2'000'000);
  for (int i = 0; i < 2; ++i) stats.RecordWall(9'000'000);  // two stray long steps
  const LoopSummary b = stats.Summarize(250'000'000);
  EXPECT_FLOAT_EQ(b.wall_max_us, 9000.0f);
  EXPECT_FLOAT_EQ(b.wall_p90_us, 2000.0f);
  EXPECT_NEAR(StepSlack(b, 100.0), 0.8, 1e-6);
  const LoopSummary c = stats.Summarize(250'000'000);  // nothing timed since
  EXPECT_DOUBLE_EQ(StepSlack(c, 100.0), 1.0);
  EXPECT_DOUBLE_EQ(StepSlack(b, 0.0), 1.0);  // rate unknown
}

}  // namespace
}  // namespace viscera::session
