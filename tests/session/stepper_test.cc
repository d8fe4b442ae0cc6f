#include "session/stepper.h"

#include <gtest/gtest.h>

#include <vector>

#include "tests/session/test_scenes.h"

namespace viscera::session {
namespace {

std::vector<mechanics::ToolTarget> Targets(int k) {
  mechanics::ToolTarget t;
  t.tip = Vec3(0.01 * k, 0.0, 0.05);
  t.jaw = (k % 20) / 20.0;
  t.active = k % 7 != 0;
  return {t};
}

TEST(Stepper, SameInputsGiveTheSameTrajectoryBitForBit) {
  const auto model = testing::SmallModel(/*num_tools=*/1);
  Stepper a(*model), b(*model);
  for (int k = 0; k < 150; ++k) {
    if (k == 60) {
      a.Reset();
      b.Reset();
    }
    a.Advance(Targets(k));
    b.Advance(Targets(k));
  }
  EXPECT_EQ(a.state().steps, 150);
  EXPECT_DOUBLE_EQ(a.state().t, 1.5);
  EXPECT_TRUE((a.state().q.array() == b.state().q.array()).all());
  EXPECT_TRUE((a.state().qd.array() == b.state().qd.array()).all());
  // and the intestine did move (it sags between its pinned ends)
  EXPECT_GT((a.state().q - model->params().initial_q).norm(), 1e-3);
}

TEST(Stepper, ResetGoesBackToTheStartButTimeCarriesOn) {
  const auto model = testing::SmallModel(0);
  Stepper s(*model);
  for (int k = 0; k < 30; ++k) s.Advance({});
  const double t = s.state().t;
  s.Reset();
  EXPECT_EQ(s.state().steps, 30);
  EXPECT_EQ(s.state().t, t);
  EXPECT_DOUBLE_EQ(t, 0.3);
  EXPECT_TRUE(s.state().q.isApprox(model->params().initial_q));
  EXPECT_EQ(s.state().qd.norm(), 0.0);
}

TEST(Stepper, ABlowUpRestoresTheLastGoodStateAndIsCounted) {
  scene::Scene scene = scene::ParseScene(testing::UnstableSceneToml(), "unstable");
  const mechanics::Model model(scene.model);
  Stepper s(model);
  int blowups = 0;
  for (int k = 0; k < 200; ++k) blowups += s.Advance({}) ? 1 : 0;
  EXPECT_GT(blowups, 0);
  EXPECT_EQ(s.recoveries(), blowups);
  EXPECT_EQ(s.state().steps, 200);  // time went on
  EXPECT_TRUE(s.state().q.allFinite());
  EXPECT_TRUE(s.state().qd.allFinite());
  EXPECT_LE(s.state().q.rowwise().norm().maxCoeff(), Stepper::kMaxDistance);
}

// The coiled scene's solves with one CG iteration: counted, and the count carries on through a
// reset, as the step count does (a session's count never goes back).
TEST(Stepper, UnconvergedSolvesAreCountedAndAResetKeepsTheCount) {
  const auto model = testing::UnconvergedModel();
  Stepper s(*model);
  for (int k = 0; k < 5; ++k) s.Advance({});
  const int64_t counted = s.state().unconverged_solves;
  EXPECT_GT(counted, 0);
  s.Reset();
  EXPECT_EQ(s.state().unconverged_solves, counted);
  s.Advance({});
  EXPECT_GT(s.state().unconverged_solves, counted);
  // the same coil with the shipped cap converges: the count is the cap's doing
  const mechanics::Model shipped(scene::ParseScene(testing::CoiledSceneToml(), "coiled").model);
  Stepper t(shipped);
  for (int k = 0; k < 5; ++k) {
    t.Advance({});
    EXPECT_GT(t.state().contacts.self, 0) << "the turns press on each other";
  }
  EXPECT_EQ(t.state().unconverged_solves, 0);
}

// Every step of the coil under 1e6 m/s² runs away and is replaced by the last good state (the
// start); the solves it counted before it ran away stay counted.
TEST(Stepper, ARecoveryKeepsTheUnconvergedSolvesCounted) {
  const auto model = testing::UnconvergedModel(-1e6);
  Stepper s(*model);
  int64_t last = 0;
  for (int k = 0; k < 5; ++k) {
    EXPECT_TRUE(s.Advance({})) << "step " << k << " was meant to run away";
    EXPECT_GT(s.state().unconverged_solves, last) << "step " << k;
    last = s.state().unconverged_solves;
  }
  EXPECT_EQ(s.recoveries(), 5);
}

}  // namespace
}  // namespace viscera::session
