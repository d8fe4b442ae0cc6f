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

}  // namespace
}  // namespace viscera::session
