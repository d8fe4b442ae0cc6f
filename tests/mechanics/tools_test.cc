// Laparoscopic tools: virtual coupling, force feedback, grasping, idling, clamping.
#include <gtest/gtest.h>

#include "mechanics/step.h"
#include "scene/scene.h"

namespace viscera::mechanics {
namespace {

// A 60 cm tube lying on a table, its ends held, and one grasper above its middle.
const char* kScene = R"(
[simulation]
rate_hz = 200
integrator = "implicit"
[intestine]
length = 0.6
radius = 0.0125
mass = 0.15
control_points = 40
stretch_stiffness = 100.0
bend_stiffness = 1.0e-4
continuous_stretch = 0.2
damping = 2.0
spring_damping = 2.0
[intestine.shape]
kind = "straight"
start = [0.0, 0.0, 0.0125]
direction = [1.0, 0.0, 0.0]
[contacts]
self = false
stiffness = 500.0
damping = 1.0
[[obstacle]]
kind = "plane"
point = [0, 0, 0]
normal = [0, 0, 1]
[[attachment]]
at = 0.0
stiffness = 50.0
[[attachment]]
at = 1.0
stiffness = 50.0
[[tool]]
name = "grasper"
port = [0.3, -0.15, 0.3]
radius = 0.0025
max_force = 5.0
)";

class Tools : public ::testing::Test {
 protected:
  void SetUp() override { Reset(scene::ParseScene(kScene).model); }
  void Reset(const ModelParams& params) {
    model_ = std::make_unique<Model>(params);
    state_ = InitialState(*model_);
    workspace_ = std::make_unique<Workspace>(*model_);
  }
  // Holds the target for `seconds`; returns the tool state at the end.
  const ToolState& Hold(const Vec3& tip, double jaw, double seconds, bool active = true) {
    ToolTarget target;
    target.tip = tip;
    target.jaw = jaw;
    target.active = active;
    const int steps = static_cast<int>(std::lround(seconds * model_->params().rate_hz));
    for (int k = 0; k < steps; ++k) Step(*model_, {{}, std::span<const ToolTarget>(&target, 1)}, &state_, workspace_.get());
    return state_.tools[0];
  }
  double MiddleHeight() const { return model_->curve().Position(state_.q, 0.5).z(); }

  std::unique_ptr<Model> model_;
  State state_;
  std::unique_ptr<Workspace> workspace_;
};

// The tube's top is at z = 2R = 25 mm; the tool (radius 2.5 mm) touches it below z = 27.5 mm.
constexpr double kTouch = 0.0275;

TEST_F(Tools, TipStartsAtTheFirstTargetAndFeelsNothingInFreeSpace) {
  const Vec3 above(0.3, 0.0, 0.12);
  const ToolState& t = Hold(above, 1.0, 0.5);
  EXPECT_LT((t.tip - above).norm(), 1e-6);
  EXPECT_LT(t.force.norm(), 1e-6);  // the tool's own weight is not felt
  EXPECT_EQ(state_.contacts.tool, 0);
}

TEST_F(Tools, PushingGivesAnOpposingForceThatGrowsWithDepth) {
  std::vector<double> forces;
  for (double depth : {0.003, 0.006, 0.012}) {
    SetUp();
    Hold(Vec3(0.3, 0.0, 0.08), 1.0, 0.2);  // start above
    const ToolState& t = Hold(Vec3(0.3, 0.0, kTouch - depth), 1.0, 1.0);
    EXPECT_GT(t.force.z(), 0.0) << depth;  // pressing down gives an upward force on the hand
    EXPECT_GT(t.force.z(), 0.8 * t.force.norm()) << depth;  // mostly opposing the push
    EXPECT_GT(t.stiffness(2, 2), 0.0) << depth;
    EXPECT_GE(state_.contacts.tool, 1);
    forces.push_back(t.force.z());
  }
  EXPECT_LT(forces[0], forces[1]);
  EXPECT_LT(forces[1], forces[2]);
}

TEST_F(Tools, AGraspLiftsTheTubeAndReleasingLetsItFallBack) {
  Hold(Vec3(0.3, 0.0, 0.06), 1.0, 0.2);
  Hold(Vec3(0.3, 0.0, kTouch), 1.0, 0.5);
  const ToolState& closed = Hold(Vec3(0.3, 0.0, kTouch), 0.0, 0.2);
  ASSERT_TRUE(closed.grasping);
  EXPECT_NEAR(closed.grasp_s, 0.5, 0.05);
  Hold(Vec3(0.3, 0.0, 0.09), 0.0, 1.0);
  EXPECT_GT(MiddleHeight(), 0.06);  // lifted by more than 5 cm
  EXPECT_LT(state_.tools[0].force.z(), 0.0);  // the hand carries the load
  const ToolState& open = Hold(Vec3(0.3, 0.0, 0.09), 1.0, 0.1);
  EXPECT_FALSE(open.grasping);
  Hold(Vec3(0.3, 0.0, 0.09), 1.0, 1.5);
  EXPECT_LT(MiddleHeight(), 0.02);  // back on the table
}

TEST_F(Tools, AnIdleDeviceFadesTheForceToZero) {
  Hold(Vec3(0.3, 0.0, 0.08), 1.0, 0.2);
  const double pushing = Hold(Vec3(0.3, 0.0, kTouch - 0.01), 1.0, 0.5).force.norm();
  ASSERT_GT(pushing, 0.5);
  const ToolState& idle = Hold(Vec3(0.3, 0.0, kTouch - 0.01), 1.0, 0.4, /*active=*/false);
  EXPECT_LT(idle.force.norm(), 0.01 * pushing);
}

TEST_F(Tools, ForceIsClampedToTheDeviceMaximum) {
  ModelParams p = scene::ParseScene(kScene).model;
  p.tools[0].max_force = 0.5;
  Reset(p);
  Hold(Vec3(0.3, 0.0, 0.08), 1.0, 0.2);
  const ToolState& t = Hold(Vec3(0.3, 0.0, 0.0), 1.0, 0.5);  // far into the tube and table
  EXPECT_TRUE(t.clamped);
  EXPECT_NEAR(t.force.norm(), 0.5, 1e-12);
}

TEST_F(Tools, NonFiniteTargetsAreIgnored) {
  Hold(Vec3(0.3, 0.0, 0.08), 1.0, 0.2);
  const Vec3 before = state_.tools[0].tip;
  const ToolState& t = Hold(Vec3(0.3, std::numeric_limits<double>::quiet_NaN(), 0.05), 1.0, 0.2);
  EXPECT_TRUE(t.tip.allFinite());
  EXPECT_TRUE(state_.q.allFinite());
  EXPECT_LT((t.tip - before).norm(), 0.01);
  EXPECT_EQ(state_.nonfinite_resets, 0);
}

}  // namespace
}  // namespace viscera::mechanics
