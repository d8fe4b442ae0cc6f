// The last line of `viscera haptic`: whether the device loop held its rate, why not, what to
// try. Both outcomes from summaries built here (a loop that held; one starved, as the demo's
// 872 of 1000 Hz at normal priority on two shared cores), so nothing is timed.
#include "client/haptic_verdict.h"

#include <gtest/gtest.h>

namespace viscera::client {
namespace {

haptic::LoopSummary Held() {
  haptic::LoopSummary s;
  s.rate_hz = 1000.0;
  s.achieved_rate_hz = 999.6;
  s.periods = 10000;
  s.misses = 3;
  s.realtime = "SCHED_FIFO 80";
  return s;
}

TEST(HapticVerdict, ALoopThatHeldSaysSo) {
  const HapticVerdict v = JudgeHapticLoop(Held(), 2);
  EXPECT_TRUE(v.held);
  EXPECT_TRUE(v.why.empty());
  EXPECT_TRUE(v.tries.empty());
  EXPECT_EQ(v.line,
            "held 1000 Hz: 999.6 Hz, 3 deadline misses in 10000 periods (0 %, limit 1 %), "
            "scheduling SCHED_FIFO 80");
  EXPECT_EQ(HapticVerdictToJson(v)["held"], true);
}

TEST(HapticVerdict, AStarvedLoopSaysWhyAndWhatToTry) {
  haptic::LoopSummary s = Held();
  s.achieved_rate_hz = 872.0;
  s.periods = 3860;
  s.misses = 217;
  s.realtime = "off";
  const HapticVerdict v = JudgeHapticLoop(s, 2);
  EXPECT_FALSE(v.held);
  ASSERT_EQ(v.why.size(), 2u);
  EXPECT_EQ(v.why[0], "it ran at 872 of 1000 Hz");
  EXPECT_EQ(v.why[1], "5.6 % of its periods missed their deadline (217 of 3860; limit 1 %)");
  ASSERT_EQ(v.tries.size(), 2u);
  EXPECT_NE(v.tries[0].find("--realtime 80"), std::string::npos);
  EXPECT_NE(v.tries[1].find("this machine has 2 core(s)"), std::string::npos);
  EXPECT_EQ(v.line.rfind("did NOT hold 1000 Hz: it ran at 872 of 1000 Hz; 5.6 %", 0), 0u) << v.line;
  EXPECT_NE(v.line.find("(scheduling off); try --realtime 80"), std::string::npos) << v.line;
  const nlohmann::ordered_json j = HapticVerdictToJson(v);
  EXPECT_EQ(j["held"], false);
  EXPECT_EQ(j["why"].size(), 2u);

  // each limit alone fails it: the rate (misses fine), then the misses (rate fine)
  haptic::LoopSummary slow = Held();
  slow.achieved_rate_hz = 980.0;
  EXPECT_FALSE(JudgeHapticLoop(slow, 8).held);
  haptic::LoopSummary missing = Held();
  missing.misses = 101;  // 1.01 %
  EXPECT_FALSE(JudgeHapticLoop(missing, 8).held);
  missing.misses = 100;  // exactly 1 %: held
  EXPECT_TRUE(JudgeHapticLoop(missing, 8).held);

  // --realtime asked and refused: say so; granted and still starved: an isolated core
  haptic::LoopSummary refused = slow;
  refused.realtime = "refused (Operation not permitted): normal scheduling";
  const HapticVerdict r = JudgeHapticLoop(refused, 8);
  EXPECT_NE(r.tries[0].find("--realtime was refused"), std::string::npos) << r.tries[0];
  const HapticVerdict f = JudgeHapticLoop(slow, 8);
  ASSERT_EQ(f.tries.size(), 1u);
  EXPECT_NE(f.tries[0].find("isolated core (taskset"), std::string::npos);
  EXPECT_FALSE(JudgeHapticLoop(haptic::LoopSummary{}, 2).held);  // no period at all
}

}  // namespace
}  // namespace viscera::client
