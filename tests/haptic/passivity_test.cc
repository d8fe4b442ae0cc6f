#include "haptic/passivity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <deque>

#include "common/check.h"

namespace viscera::haptic {
namespace {

TEST(PassivityObserver, CountsTheExactWorkOfTheHeldForce) {
  PassivityController pc(false, 10.0);
  pc.Observe(Vec3(0, 0, 0));
  pc.Commit(Vec3(0, 0, 2.0));  // 2 N up held while the hand moves 1 cm down: 0.02 J absorbed
  pc.Observe(Vec3(0, 0, -0.01));
  EXPECT_NEAR(pc.energy_j(), 0.02, 1e-15);
  pc.Commit(Vec3(1.0, 0, 2.0));  // then 2 cm up and 1 cm along x: 2 * 0.02 + 1 * 0.01 J given back
  pc.Observe(Vec3(0.01, 0, 0.01));
  EXPECT_NEAR(pc.energy_j(), 0.02 - 0.05, 1e-15);
  EXPECT_NEAR(pc.min_energy_j(), -0.03, 1e-15);
}

// The hand moves sinusoidally into a spring rendered with a delay (a delayed answer is the
// classic source of energy): the observer sees energy created without the controller, and with
// it the port stays passive up to the last period's prediction.
struct DelayedSpringRun {
  double final_energy, min_energy, dissipated;
  int64_t activations;
  double sampling_energy;  // k/2 sum |dx|^2: what holding a spring's force over a period creates
};

DelayedSpringRun RunDelayedSpring(bool controller, int delay_periods) {
  const double T = 1e-3, k = 300.0;
  PassivityController pc(controller, 50.0);
  std::deque<Vec3> delayed;
  Vec3 x_prev = Vec3::Zero();
  double sampling = 0.0;
  for (int n = 0; n < 4000; ++n) {
    const Vec3 x(0, 0, -0.005 * (1.0 - std::cos(2 * M_PI * 2.0 * n * T)));  // in and out, 2 Hz
    pc.Observe(x);
    delayed.push_back(-k * x);
    const Vec3 spring =
        delayed.size() > static_cast<size_t>(delay_periods) ? delayed.front() : Vec3::Zero();
    if (delayed.size() > static_cast<size_t>(delay_periods)) delayed.pop_front();
    const Vec3 f = pc.Control(spring, (x - x_prev) / T, T);
    pc.Commit(f);
    sampling += 0.5 * k * (x - x_prev).squaredNorm();
    x_prev = x;
  }
  return {pc.energy_j(), pc.min_energy_j(), pc.dissipated_j(), pc.activations(), sampling};
}

TEST(PassivityController, KeepsADelayedSpringPassiveAndTheObserverShowsItMatters) {
  const DelayedSpringRun off = RunDelayedSpring(false, 20);
  const DelayedSpringRun on = RunDelayedSpring(true, 20);
  // without the controller: energy created, about k x0^2 per cycle times the phase lag
  EXPECT_LT(off.final_energy, -1e-3);
  EXPECT_EQ(off.activations, 0);
  // with it: never more than a period's prediction error below zero, and it did the work
  EXPECT_GE(on.min_energy, -1e-5);
  EXPECT_GE(on.final_energy, -1e-5);
  EXPECT_GT(on.activations, 100);
  EXPECT_GT(on.dissipated, 0.5 * -off.final_energy);
}

TEST(PassivityController, LeavesAPassiveSpringAlmostAlone) {
  const DelayedSpringRun on = RunDelayedSpring(true, 0);
  // a sampled spring with no delay only creates the zero-order-hold energy k |dx|^2 / 2 per
  // period: the controller removes that and no more
  EXPECT_GE(on.final_energy, -1e-5);
  EXPECT_LT(on.dissipated, 1.05 * on.sampling_energy);
  EXPECT_GT(on.dissipated, 0.5 * on.sampling_energy);
}

TEST(PassivityController, NeverAddsMoreThanItsDampingLimit) {
  PassivityController pc(true, 2.0);
  pc.Observe(Vec3::Zero());
  pc.Commit(Vec3(0, 0, -5.0));  // pushes the hand down while it moves down: 0.05 J created
  pc.Observe(Vec3(0, 0, -0.01));
  const Vec3 v(0, 0, -0.1);
  const Vec3 f = pc.Control(Vec3(0, 0, -5.0), v, 1e-3);
  EXPECT_DOUBLE_EQ(pc.last_damping(), 2.0);
  EXPECT_NEAR((f - Vec3(0, 0, -5.0 + 0.2)).norm(), 0.0, 1e-12);
  EXPECT_THROW(PassivityController(true, -1.0), InputError);
}

}  // namespace
}  // namespace viscera::haptic
