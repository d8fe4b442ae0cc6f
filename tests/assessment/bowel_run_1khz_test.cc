// The expert's whole run of scenes/bowel_run.toml at 1 kHz, offline: the same hand over hand as
// at 100 Hz (tests/assessment/bowel_run_test.cc), every segment grasped in order, nothing hurt,
// and every pass mark met. Its own binary and test: 145 s of 1 kHz steps, a minute or two of one
// core, run beside the others.
#include <gtest/gtest.h>

#include "tests/assessment/bowel_run_play.h"

namespace viscera::assessment {
namespace {

TEST(BowelRun, TheExpertsWholeRunAt1kHzCoversEverySegmentInOrderUnhurtAndPasses) {
  const bowel_run::Played run = bowel_run::Play("expert", 145.3, 1000.0);
  EXPECT_EQ(run.report.grasps, 90);
  bowel_run::ExpectCoveredInOrderUnhurt(run, 89);
  EXPECT_EQ(run.report.coverage, 1.0);
  EXPECT_EQ(run.report.reversals, 0);
  EXPECT_TRUE(run.report.passed) << assessment::FormatRunning(run.report);
}

}  // namespace
}  // namespace viscera::assessment
