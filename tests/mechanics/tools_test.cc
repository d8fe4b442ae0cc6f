// Laparoscopic tools: virtual coupling, force feedback, grasping, idling, clamping.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <vector>

#include "mechanics/step.h"
#include "scene/scene.h"
#include "tests/mechanics/table_scene.h"

namespace viscera::mechanics {
namespace {

// A 60 cm tube lying on a table, its ends held, and one grasper above its middle.
const char* kScene = viscera::testing::kTableScene;
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
    for (int k = 0; k < steps; ++k)
      Step(*model_, {{}, std::span<const ToolTarget>(&target, 1)}, &state_, workspace_.get());
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

TEST_F(Tools, ATipThatStopsShortOfTheTubeFeelsWhatItFeelsInFreeSpace) {
  // The same approach twice: down at 0.5 m/s to 2.5 mm above the tube's top, then held; and 10 cm
  // higher, where nothing is near. A pair closing fast acts before it touches (speculative), but
  // the tissue only ever pushes: the hand must feel nothing of a tube the tip never reaches.
  // (Held linear, the speculative contact pulled the hand 0.23 N toward the tube.)
  double lowest_tip = 1.0;
  auto approach = [&](double lift) {
    ModelParams params = scene::ParseScene(kScene).model;
    params.rate_hz = 100.0;  // 10 ms steps: a pair closing at 0.5 m/s acts from 5 mm away
    Reset(params);
    std::vector<Vec3> forces;
    const double stop = kTouch + 0.0025 + lift;
    const double start = stop + 0.05;
    const int steps = static_cast<int>(std::lround(0.4 * model_->params().rate_hz));
    for (int k = 0; k <= steps; ++k) {
      const double t = k / model_->params().rate_hz;
      const ToolState& tool = Hold(Vec3(0.3, 0.0, std::max(stop, start - 0.5 * t)), 1.0,
                                   1.0 / model_->params().rate_hz);
      forces.push_back(tool.force);
      lowest_tip = std::min(lowest_tip, tool.tip.z() - lift);
    }
    return forces;
  };
  const std::vector<Vec3> near = approach(0.0), free = approach(0.1);
  ASSERT_EQ(near.size(), free.size());
  double worst = 0.0;
  for (size_t k = 0; k < near.size(); ++k) worst = std::max(worst, (near[k] - free[k]).norm());
  EXPECT_LT(worst, 1e-3) << "N: the tube pulled the tool before it touched";
  EXPECT_GT(lowest_tip, kTouch) << "the tip touched the tube: the test lost its point";
}

// A tip at rest a hair above the tube has no contact in the solve when its target jumps 1 cm into
// the tube: the pair that the solve drives into contact must still act within the 10 ms step
// (its law given to the tip from the sub-step's start). Activated only when the tip already had a
// contact, it was passed by: the tip ended the step 19 % of R deep.
TEST_F(Tools, ATipJustApartFromTheTubeMeetsItWithinTheStep) {
  ModelParams params = scene::ParseScene(kScene).model;
  params.rate_hz = 100.0;
  Reset(params);
  const ToolState& rest = Hold(Vec3(0.3, 0.0, kTouch + 1e-4), 1.0, 1.0);
  ASSERT_LT(rest.force.norm(), 1e-6) << "N: the tip must rest apart from the tube";
  double deepest = 0.0;
  for (int k = 0; k < 30; ++k) {
    Hold(Vec3(0.3, 0.0, kTouch - 0.01), 1.0, 0.01);
    if (!std::isnan(state_.contacts.min_clearance))
      deepest = std::max(deepest, -state_.contacts.min_clearance / params.radius);
  }
  EXPECT_GE(state_.contacts.tool, 1) << "the tip must end on the tube";
  EXPECT_LE(deepest, 0.10);
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

// The tool coming down at 10 cm/s and pressing the tube into the table with the device's whole
// 5 N, at 100 Hz and 1 kHz: the tube is trapped, so only the contact law stops the tool (measured:
// 7.7 % of R at both rates). The control: the law linear everywhere (impact_depth = 0) lets the
// tool sink by force / k (61 % of R at 1 kHz).
TEST_F(Tools, AToolPressingTheTubeIntoTheTableSinksAtMostATenthOfTheRadius) {
  auto deepest = [&](double rate_hz, double impact_depth, double* force) {
    ModelParams p = scene::ParseScene(kScene).model;
    p.rate_hz = rate_hz;
    p.contacts.impact_depth = impact_depth;
    Reset(p);
    Hold(Vec3(0.3, 0.0, 0.08), 1.0, 0.2);
    double worst = 0.0;
    const int steps = static_cast<int>(std::lround(1.5 * rate_hz));
    for (int k = 0; k < steps; ++k) {
      // down at 10 cm/s to the tube's bottom: far into it
      Hold(Vec3(0.3, 0.0, std::max(0.0, 0.08 - 0.1 * (k + 1) / rate_hz)), 1.0, 1.0 / rate_hz);
      worst = std::max(worst, -state_.contacts.min_clearance);
    }
    *force = state_.tools[0].force.norm();  // friction tilts it from the vertical
    return worst / p.radius;
  };
  for (double rate : {100.0, 1000.0}) {
    double force = 0.0;
    EXPECT_LE(deepest(rate, ContactParams{}.impact_depth, &force), 0.10) << rate << " Hz";
    EXPECT_GT(force, 0.99 * 5.0) << rate << " Hz: the press must reach the device's maximum";
  }
  double force = 0.0;
  EXPECT_GT(deepest(1000.0, 0.0, &force), 0.33) << "linear law";
}

TEST_F(Tools, AGraspLiftsTheTubeAndReleasingLetsItFallBack) {
  Hold(Vec3(0.3, 0.0, 0.06), 1.0, 0.2);
  Hold(Vec3(0.3, 0.0, kTouch), 1.0, 0.5);
  const ToolState& closed = Hold(Vec3(0.3, 0.0, kTouch), 0.0, 0.2);
  ASSERT_TRUE(closed.grasping);
  EXPECT_NEAR(closed.grasp_s, 0.5, 0.05);
  Hold(Vec3(0.3, 0.0, 0.09), 0.0, 1.0);
  EXPECT_GT(MiddleHeight(), 0.06);            // lifted by more than 5 cm
  EXPECT_LT(state_.tools[0].force.z(), 0.0);  // the hand carries the load
  const ToolState& open = Hold(Vec3(0.3, 0.0, 0.09), 1.0, 0.1);
  EXPECT_FALSE(open.grasping);
  Hold(Vec3(0.3, 0.0, 0.09), 1.0, 1.5);
  EXPECT_LT(MiddleHeight(), 0.02);  // back on the table
}

// The jaws hold the tube where they close on it, not at the nearest of its collision spheres
// (12.5 mm apart here): closed at offsets that sweep across two spheres, the grasped point lies
// under the tip every time. Snapped to a sphere centre it was up to 6 mm off, and a tip half way
// between two spheres grasped one or the other by a hair (the clearing gesture pulled loops 1 cm
// apart at 100 Hz and 1 kHz).
TEST_F(Tools, TheJawsGraspTheTubeWhereTheyCloseNotAtASphereCentre) {
  for (const double dx : {0.0, 0.003, 0.00625, 0.009, 0.0125}) {
    SetUp();
    const Vec3 tip(0.3 + dx, 0.0, kTouch);
    Hold(tip + Vec3(0.0, 0.0, 0.03), 1.0, 0.2);
    Hold(tip, 1.0, 0.3);
    const ToolState& closed = Hold(tip, 0.0, 1.0 / model_->params().rate_hz);
    ASSERT_TRUE(closed.grasping) << dx;
    const Vec3 held = model_->curve().Position(state_.q, closed.grasp_s);
    EXPECT_NEAR(held.x(), closed.tip.x(), 0.001) << "tip " << dx * 1e3 << " mm from the middle";
  }
}

// A device that stops sending must not be kicked: the force fades over steps, never drops
// at once, never comes back up, and is gone within a few of the coupling's 0.05 s time
// constants (the felt force lags the coupling's scale a little: as the coupling weakens,
// the tube pushes the tip further from the target).
TEST_F(Tools, AHandPullingAGraspedLoopFartherThanTheDeviceCanHoldDoesNotShakeIt) {
  // Grasp the middle, then the hand jumps 30 cm up and stays: the ends' attachments hold the
  // tube, so the coupling saturates at the device's 5 N. The tip must come to rest where the
  // 5 N balance the tissue, not bounce around it.
  Hold(Vec3(0.3, 0.0, 0.06), 1.0, 0.2);
  Hold(Vec3(0.3, 0.0, kTouch), 1.0, 0.5);
  ASSERT_TRUE(Hold(Vec3(0.3, 0.0, kTouch), 0.0, 0.2).grasping);
  Hold(Vec3(0.3, 0.0, kTouch + 0.3), 0.0, 1.5);
  double fastest = 0.0, lowest = 1.0, highest = 0.0;
  for (int k = 0; k < 100; ++k) {  // the next 0.5 s
    const ToolState& t = Hold(Vec3(0.3, 0.0, kTouch + 0.3), 0.0, 0.005);
    fastest = std::max(fastest, t.tip_velocity.norm());
    lowest = std::min(lowest, t.tip.z());
    highest = std::max(highest, t.tip.z());
  }
  EXPECT_LT(fastest, 0.05) << "m/s";
  EXPECT_LT(highest - lowest, 0.005) << "m: the tip still bounces";
  EXPECT_TRUE(state_.tools[0].clamped);  // it was the saturated case
}

TEST_F(Tools, AnIdleDeviceFadesTheForceToZeroStepByStep) {
  Hold(Vec3(0.3, 0.0, 0.08), 1.0, 0.2);
  const double pushing = Hold(Vec3(0.3, 0.0, kTouch - 0.01), 1.0, 0.5).force.norm();
  ASSERT_GT(pushing, 0.5);
  const double h = 1.0 / model_->params().rate_hz;
  std::vector<double> f = {pushing};  // f[0]: the last active step; f[k]: k steps idle
  for (int k = 1; k * h <= 0.4 + 1e-9; ++k)
    f.push_back(Hold(Vec3(0.3, 0.0, kTouch - 0.01), 1.0, h, false).force.norm());
  EXPECT_GE(f[1], 0.5 * f[0]) << "the force dropped at once";
  for (size_t k = 1; k < f.size(); ++k)
    EXPECT_LE(f[k], f[k - 1] * (1.0 + 1e-9)) << "rose again at idle step " << k;
  const auto at = [&](double t) { return f[static_cast<size_t>(std::lround(t / h))]; };
  for (double t : {0.05, 0.1, 0.2, 0.3, 0.4})
    std::printf("idle %.2f s: %.4f of the force\n", t, at(t) / pushing);
  // the coupling's scale is exp(-t / 0.05 s) (docs/protocol.md)
  EXPECT_LT(at(0.1), 0.5 * pushing);
  EXPECT_LT(at(0.3), 0.02 * pushing);
  EXPECT_LT(at(0.4), 0.01 * pushing);
}

// The local stiffness K the device renders between answers (F + dF = F - K dx) against an
// independent oracle: central differences of the settled force over the tip's target, on a
// tube held rigid so that only the tool moves. Along the contact normal n they must agree.
// Across it they do not, by design: a tool pressed on a convex surface (radius rho = tube +
// tool radius) has a negative tangential stiffness of about |F| / rho (it slides off the top),
// which K leaves out so that it stays symmetric and PSD, the restoring-only model a device can
// render passively. The test bounds that omission too, so neither part can drift unnoticed.
TEST_F(Tools, LocalStiffnessMatchesFiniteDifferencesOfTheForce) {
  ModelParams p = scene::ParseScene(kScene).model;
  // The normal contact's stiffness: static friction's tangential spring holds wherever it stuck,
  // so a force reached from two sides differs by its hysteresis, which no K describes.
  p.contacts.tool_friction = 0.0;
  const int n = static_cast<int>(p.initial_q.rows());
  p.pinned.clear();
  for (int i = 0; i < n; ++i) p.pinned.push_back(static_cast<double>(i) / (n - 1));  // a rigid tube
  const double rho = p.radius + p.tools[0].radius;
  for (const Vec3& dir :
       {Vec3(0.0, 0.0, -1.0), Vec3(0.0, 0.6, -0.8)}) {  // straight down, and oblique
    SCOPED_TRACE(::testing::Message() << "push along " << dir.transpose());
    const Vec3 normal = -dir;                                    // from the tube's axis to the tool
    const Vec3 surface = Vec3(0.3, 0.0, 0.0125) + rho * normal;  // where the tool's side touches
    auto settled = [&](const Vec3& target) {
      Reset(p);
      Hold(surface + 0.05 * normal, 1.0, 0.2);  // arrive from outside
      ToolState t = Hold(target, 1.0, 2.0);
      EXPECT_LT(t.tip_velocity.norm(), 1e-6) << "not settled: " << t.tip_velocity.transpose();
      return t;
    };
    const Vec3 base_target = surface - 0.0025 * normal;  // 2.5 mm in
    const ToolState base = settled(base_target);
    const Mat3& K = base.stiffness;
    ASSERT_GT(K.norm(), 1.0) << "no contact at the base pose";
    EXPECT_LE((K - K.transpose()).norm(), 1e-9 * K.norm());
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (K + K.transpose()));
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-9 * K.norm());
    const Mat3 across = Mat3::Identity() - normal * normal.transpose();
    const double d = 0.001;
    for (int axis = 0; axis < 3; ++axis) {
      const Vec3 delta = 2.0 * d * Vec3::Unit(axis);  // central difference: +d and -d
      const Vec3 dF =
          settled(base_target + 0.5 * delta).force - settled(base_target - 0.5 * delta).force;
      const Vec3 predicted = -K * delta;  // restoring: the hand is pushed back
      const Vec3 miss = dF - predicted;
      const double scale = K.norm() * delta.norm();
      EXPECT_LE(std::abs(normal.dot(miss)), 0.2 * std::max(std::abs(normal.dot(dF)), 0.1 * scale))
          << "axis " << axis << "\nK =\n"
          << K << "\ndF = " << dF.transpose();
      // what K leaves out: tangential, destabilizing, of size |F| / rho (within 30 %)
      const Vec3 slide = across * delta;
      EXPECT_LE((across * miss - base.force.norm() / rho * slide).norm(),
                0.3 * base.force.norm() / rho * slide.norm() + 1e-4 * scale)
          << "axis " << axis << ": tangential miss " << (across * miss).transpose()
          << ", |F| / rho = " << base.force.norm() / rho;
    }
    EXPECT_LT((state_.q - p.initial_q).cwiseAbs().maxCoeff(), 1e-3)
        << "the tube was meant to stay put";
  }
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
