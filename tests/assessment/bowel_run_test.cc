// Running the bowel end to end, offline: scenes/bowel_run.toml played by its scripted runs
// (tools/bowel_run_script.py writes them), scored step by step as a session is: the expert
// covers every segment, in order, and hurts none, over the whole bowel at 100 Hz (at 1 kHz:
// tests/assessment/bowel_run_1khz_test.cc); the rough novice's shut jaws pinch the segments they
// grasp and its yank breaks the traction threshold there, and nowhere else; the careless novice
// misses the segments it jumps over and only those.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "tests/assessment/bowel_run_play.h"

namespace viscera::assessment {
namespace {

using bowel_run::ExpectCoveredInOrderUnhurt;
using bowel_run::Play;
using bowel_run::Played;

// The expert's whole run at 100 Hz: 90 grasps, every segment of the 4.5 m, and it passes.
TEST(BowelRun, TheExpertCoversEverySegmentInOrderUnhurtAt100Hz) {
  const Played run = Play("expert", 145.3, 100.0);
  EXPECT_EQ(run.report.grasps, 90);
  ExpectCoveredInOrderUnhurt(run, 89);
  EXPECT_EQ(run.report.coverage, 1.0);
  EXPECT_TRUE(run.report.passed) << FormatRunning(run.report);
}

// The rough run shuts the jaws at two grasps and yanks the bowel up at the second: a pinch at
// each of those segments, a traction event at the yanked one, and no other event.
void ExpectRoughPinchesAndTearsWhereItShutsAndYanks() {
  const Played run = Play("rough", 33.0, 100.0);
  ASSERT_EQ(run.nonfinite_resets, 0);
  ASSERT_EQ(run.shut.size(), 2u);
  std::set<int> pinched, torn;
  for (const DamageEvent& e : run.report.events) {
    if (e.kind == "pinch") pinched.insert(e.segment);
    if (e.kind == "traction") torn.insert(e.segment);
    EXPECT_NE(e.kind, "dose") << "at segment " << e.segment;
  }
  EXPECT_EQ(pinched, run.shut);
  EXPECT_EQ(torn, std::set<int>{*run.shut.rbegin()});
  EXPECT_GE(run.report.max_traction, run.report.traction_break);
}

// The careless run jumps 20 cm at two grasps here: the segments it jumps over are missed, every
// other segment up to its last grasp is covered.
void ExpectCarelessMissesTheSkippedSegmentsAndOnlyThose() {
  const Played run = Play("careless", 36.0, 100.0);
  ASSERT_EQ(run.nonfinite_resets, 0);
  std::set<int> skipped;
  for (int k = 0; k <= *run.aimed.rbegin(); ++k)
    if (!run.aimed.count(k)) skipped.insert(k);
  ASSERT_EQ(skipped.size(), 6u) << "two jumps over three segments each";
  std::set<int> missed;
  for (int k = 0; k <= run.last_segment; ++k)
    if (!run.covered[static_cast<size_t>(k)]) missed.insert(k);
  EXPECT_EQ(run.last_segment, *run.aimed.rbegin());
  EXPECT_EQ(missed, skipped);
  EXPECT_TRUE(run.report.events.empty());
}

// The novices' first 20-22 grasps at 100 Hz, each failing for its own reason (one test, one
// settle of the scene).
TEST(BowelRun, TheRoughNovicePinchesAndTearsTheCarelessOneMissesWhatItSkips) {
  {
    SCOPED_TRACE("rough");
    ExpectRoughPinchesAndTearsWhereItShutsAndYanks();
  }
  {
    SCOPED_TRACE("careless");
    ExpectCarelessMissesTheSkippedSegmentsAndOnlyThose();
  }
}

}  // namespace
}  // namespace viscera::assessment
