// The implicit step's linearization guard (docs/integrators.md, "One linearization per sub-step"):
// a sub-step that turns a segment of the control polygon so far that its single linearization
// misses the stretch is done again as two halves.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "mechanics/implicit_euler.h"
#include "mechanics/linearization_guard.h"
#include "mechanics/step.h"
#include "scene/scene.h"

namespace viscera::mechanics {
namespace {

// Three points along x, 1 apart; the motion that moves the last by `last` and the others not at
// all.
Points Line() {
  Points q(3, 3);
  q << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  return q;
}
Points MovingLast(const Vec3& last) {
  Points dq = Points::Zero(3, 3);
  dq.row(2) = last.transpose();
  return dq;
}
bool Within(const Vec3& last, double limit) {
  return LinearizationGuard::UnseenStretchWithin(Line(), MovingLast(last), limit);
}
double Unseen(const Vec3& last) {
  return LinearizationGuard::UnseenStretch(Line(), MovingLast(last));
}

TEST(LinearizationGuard, ATurnOfThetaLeavesAboutHalfThetaSquaredUnseen) {
  // The last segment turned by 0.3 rad, its length kept: to first order it shortened to cos 0.3
  // and moved sin 0.3 sideways: sin² 0.3 / 2 cos 0.3 = 0.045708 of it unseen (~θ²/2).
  const double theta = 0.3;
  const Vec3 turned = Vec3(1.0 + std::cos(theta), std::sin(theta), 0.0) - Vec3(2.0, 0.0, 0.0);
  EXPECT_TRUE(Within(turned, 0.04571));
  EXPECT_FALSE(Within(turned, 0.04570));
  EXPECT_NEAR(Unseen(turned), std::pow(std::sin(theta), 2) / (2.0 * std::cos(theta)), 1e-15);
  EXPECT_EQ(Unseen(Vec3(-2.0, 0.0, 0.0)), std::numeric_limits<double>::infinity());
  // Stretching along the segment and moving everything alike are seen exactly.
  EXPECT_TRUE(Within(Vec3(0.5, 0.0, 0.0), 1e-12));
  EXPECT_TRUE(Within(Vec3(-0.5, 0.0, 0.0), 1e-12));
  Points q(2, 3);
  q << 0, 0, 0, 0, 1, 0;
  const Points shift = Vec3(0.3, -2.0, 7.0).transpose().replicate(2, 1);
  EXPECT_TRUE(LinearizationGuard::UnseenStretchWithin(q, shift, 1e-12));
  // A segment turned inside out (first order: length -1) is never within.
  EXPECT_FALSE(Within(Vec3(-2.0, 0.0, 0.0), 100.0));
  // Coincident points have no direction to linearize along: skipped, not NaN.
  Points twice = Points::Zero(2, 3);
  EXPECT_TRUE(LinearizationGuard::UnseenStretchWithin(twice, Points::Ones(2, 3), 0.0));
}

struct Session {
  std::unique_ptr<Model> model;
  State state;
  std::unique_ptr<Workspace> workspace;
  double start_energy = 0.0;
  double largest_gain = -1.0;  // of one step (J)
  int gaining_steps = 0;
};

// `scene` from scenes/ at `rate` for `seconds`; with the guard as `guard`.
Session Simulate(const char* scene, double rate, double seconds, bool guard) {
  scene::Scene s = scene::LoadSceneFile(std::string(VISCERA_SOURCE_DIR) + "/scenes/" + scene);
  scene::ChangeRate(&s.model, rate);
  s.model.linearization_guard = guard;
  Session r;
  r.model = std::make_unique<Model>(s.model);
  r.state = InitialState(*r.model);
  r.workspace = std::make_unique<Workspace>(*r.model);
  Interactions* in = r.workspace->interactions();
  double previous = ComputeEnergies(*r.model, r.state.q, r.state.qd, in).total();
  r.start_energy = previous;
  const int steps = static_cast<int>(std::lround(seconds * rate));
  for (int k = 0; k < steps; ++k) {
    Step(*r.model, {}, &r.state, r.workspace.get());
    const double e = ComputeEnergies(*r.model, r.state.q, r.state.qd, in).total();
    r.largest_gain = std::max(r.largest_gain, e - previous);
    if (e > previous + 1e-6 * r.start_energy) ++r.gaining_steps;
    previous = e;
  }
  return r;
}

int64_t Halved(Session& r) {
  return dynamic_cast<ImplicitEulerIntegrator&>(r.workspace->integrator()).halved_substeps();
}

// attached.toml's mesentery springs start 14 cm past their rest length: 2.8 N on a slack tube
// whose sideways stiffness is zero to first order. At 100 Hz the one linearization let a point
// fly 8.5 cm in the first step (stretch energy 0.13 J -> 43 J, then 1.3 J of motion from
// rest). fallopian.toml's mesosalpinx does the same, smaller, at 200 and 250 Hz.
TEST(LinearizationGuard, ScenesStartingOutOfBalanceGainNoEnergyAtAnyRate) {
  for (const char* scene : {"attached.toml", "fallopian.toml"}) {
    for (const double rate : {100.0, 150.0, 200.0, 250.0, 300.0}) {
      Session r = Simulate(scene, rate, 1.0, true);
      EXPECT_EQ(r.gaining_steps, 0)
          << scene << " at " << rate << " Hz: largest gain " << r.largest_gain << " J";
    }
  }
}

// The safeguard: the same first step without the guard.
TEST(LinearizationGuard, WithoutItTheOverstretchedMesenteryInjectsEnergy) {
  Session off = Simulate("attached.toml", 100.0, 0.05, false);
  EXPECT_GT(off.largest_gain, 1.0) << "J in one step";
  EXPECT_EQ(Halved(off), 0);
  Session on = Simulate("attached.toml", 100.0, 0.05, true);
  EXPECT_LT(on.largest_gain, 0.0);
  EXPECT_GT(Halved(on), 0);
  Session fallopian = Simulate("fallopian.toml", 200.0, 0.05, false);
  EXPECT_GT(fallopian.largest_gain, 1e-4) << "J in one step";
}

// Halving allocates nothing and reruns bit for bit (Step's contract).
TEST(LinearizationGuard, HalvedStepsAreBitIdenticalOnRerun) {
  Session a = Simulate("attached.toml", 100.0, 0.2, true);
  Session b = Simulate("attached.toml", 100.0, 0.2, true);
  ASSERT_GT(Halved(a), 0);
  EXPECT_EQ(Halved(a), Halved(b));
  EXPECT_TRUE((a.state.q.array() == b.state.q.array()).all());
  EXPECT_TRUE((a.state.qd.array() == b.state.qd.array()).all());
}

}  // namespace
}  // namespace viscera::mechanics
