// Energy through an impact (the goal: on a 55 cm drop of scenes/fall.toml the energy never grows
// without input). The coil of scenes/fall.toml released with its lowest point 55 cm above the
// plane (impact_test.cc's convention), no input: the total energy (kinetic, gravity, elastic,
// contact) after each step must never exceed the step before's by more than round-off, through
// the fall, the impact and the landing.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>

#include "mechanics/implicit_euler.h"
#include "tests/mechanics/fall_record.h"

namespace viscera::mechanics {
namespace {

constexpr double kHeight = 0.55;    // m
constexpr double kSeconds = 1.5;    // impact at ~0.33 s; the landing and the pile sliding after it
constexpr double kRoundOff = 1e-9;  // of the energy at release: far above double round-off on ~6 J

// The controls below run the fall with μ = 0.3 against the plane and itself, where switching a
// safeguard off shows a gain; with the tissue card's μ (the scene's) they happen not to gain.
constexpr double kControlFriction = 0.3;

// scenes/fall.toml at rate_hz; friction >= 0: that μ against the plane and itself instead of the
// scene's.
ModelParams Fall(double rate_hz, double friction) {
  ModelParams p = scene::LoadSceneFile(VISCERA_SOURCE_DIR "/scenes/fall.toml").model;
  scene::ChangeRate(&p, rate_hz);
  if (friction >= 0.0) p.contacts.friction = p.contacts.self_friction = friction;
  return p;
}

// held = false: the impact limiter and the stiffening law alone, without the impulses inside the
// implicit solve and the material spheres that are on by default (docs/impacts.md);
// friction: as Fall's.
FallRecord Drop(double rate_hz, double impact_depth = -1.0, bool held = true,
                double friction = -1.0) {
  ModelParams p = Fall(rate_hz, friction);
  if (impact_depth >= 0.0) p.contacts.impact_depth = impact_depth;
  p.contacts.impact_constraints = held;
  p.contacts.spheres_follow_material = held;
  return RecordFall(DroppedFrom(p, kHeight), kSeconds);
}

// No step ends with more energy than the step before it (beyond round-off), and the drop ends
// with little of its energy left.
void ExpectNoStepGains(double rate_hz, bool held) {
  const FallRecord r = Drop(rate_hz, -1.0, held);
  EXPECT_LE(r.LargestGain(), kRoundOff * r.start_energy) << rate_hz << " Hz: " << Describe(r);
  EXPECT_LT(r.energy.back(), 0.1 * r.start_energy)
      << rate_hz << " Hz: it landed and the impact dissipated";
}

// The goal, with the defaults: the impulses inside the implicit solve and spheres that follow the
// material never let a step gain, at any rate.
TEST(DropEnergy, FiftyFiveCentimetreDropNeverGainsEnergyAtAnyRate) {
  for (double rate : {100.0, 250.0, 500.0, 1000.0}) ExpectNoStepGains(rate, true);
}

// The limiter and the stiffening law alone (no impulses inside the solve, spheres not following
// the material) still never gain up to 500 Hz: that path stays selectable from a scene
// (impact_constraints = false). 500 Hz holds only since the CG warm start of 256e214 (it gained
// 1.5 mJ in one step before): whether an impact gains is sensitive to the solve's round-off.
TEST(DropEnergy, TheLimiterAloneNeverGainsEnergyAt100To500Hz) {
  for (double rate : {100.0, 250.0, 500.0}) ExpectNoStepGains(rate, false);
}

// A known defect of the limiter-only path, asserted so that the check above is seen to catch a
// real gain (and so that the day the path stops gaining is noticed): if that path is fixed,
// replace this with ExpectNoStepGains(1000.0, false) and show the check failing another way.
// The safeguard, shown by switching it off: at μ 0.3 the limiter and the law alone gain at 1 kHz
// (four steps, the worst 22 mJ, +1.6 % of the step before, at the impact, mostly elastic, while a
// self pair is 15 % of R deep in the law's stiffening range, linearized once per sub-step). So the
// check above catches a real gain.
TEST(DropEnergy, WithoutTheImpulsesInsideTheSolveTheDropGainsAt1kHz) {
  const FallRecord r = Drop(1000.0, -1.0, false, kControlFriction);
  EXPECT_GT(r.LargestGain(), 1e-3 * r.start_energy) << Describe(r);
}

// The shipped fall as it runs, 3 s (the impact, the landing, the pile sliding): the largest gain of
// one step, the energy at release and the deepest pair (fraction of R).
struct ShippedFall {
  double largest_gain, start_energy, deepest;
};

// stick_slip: Coulomb's law with a static phase (the default), else the regularized law;
// floor_share > 0: CG's stop floored at that share of gravity's impulse instead of the default;
// friction: as Fall's.
ShippedFall RunShippedFall(double rate_hz, bool impact_redo, bool stick_slip = false,
                           double floor_share = 0.0, double friction = -1.0) {
  ModelParams p = Fall(rate_hz, friction);
  p.contacts.friction_law = stick_slip ? FrictionLaw::kStickSlip : FrictionLaw::kRegularized;
  const Model model(p);
  State s = InitialState(model);
  Workspace ws(model);
  auto& integrator = dynamic_cast<ImplicitEulerIntegrator&>(ws.integrator());
  integrator.set_impact_redo(impact_redo);
  if (floor_share > 0.0) integrator.set_gravity_floor(floor_share);
  Interactions* in = ws.interactions();
  double previous = ComputeEnergies(model, s.q, s.qd, in).total();
  ShippedFall f{-std::numeric_limits<double>::infinity(), previous, 0.0};
  for (int k = 0; k < static_cast<int>(std::lround(3.0 * rate_hz)); ++k) {
    Step(model, {}, &s, &ws);
    const double e = ComputeEnergies(model, s.q, s.qd, in).total();
    f.largest_gain = std::max(f.largest_gain, e - previous);
    previous = e;
    if (!std::isnan(s.contacts.min_clearance))
      f.deepest = std::max(f.deepest, -s.contacts.min_clearance / p.radius);
  }
  return f;
}

// The implicit step's BDF2 sub-steps that would need impact or depth constraints are done again
// as backward Euler (docs/integrators.md, "Numerical damping: why BDF2"): the shipped fall then
// gains in no step and no pair sinks past 10 % of R.
TEST(DropEnergy, TheShippedFallRunsBdf2AndNeverGainsEnergy) {
  for (double rate : {250.0, 500.0, 1000.0}) {
    const ShippedFall f = RunShippedFall(rate, true);
    EXPECT_LE(f.largest_gain, kRoundOff * f.start_energy) << rate << " Hz";
    EXPECT_LE(f.deepest, 0.1) << rate << " Hz";
  }
}

// The control: BDF2 stepping through its impacts (the constraints, which assume backward Euler's
// kinematics, never called) gains 3.5 mJ in a step at 500 Hz and μ 0.3, a million times what the
// test above allows.
TEST(DropEnergy, WithoutTheBackwardEulerRedoTheShippedFallGains) {
  const ShippedFall f = RunShippedFall(500.0, false, false, 0.0, kControlFriction);
  EXPECT_GT(f.largest_gain, 1e-5 * f.start_energy);
}

// With Coulomb's static phase the pile comes to rest, held by stuck tangential springs: CG's stop,
// floored at a share of gravity's impulse, must leave it resting without gaining energy.
TEST(DropEnergy, UnderStickSlipFrictionTheShippedFallNeverGainsEnergy) {
  for (double rate : {250.0, 1000.0}) {
    const ShippedFall f = RunShippedFall(rate, true, true);
    EXPECT_LE(f.largest_gain, kRoundOff * f.start_energy) << rate << " Hz";
    EXPECT_LE(f.deepest, 0.1) << rate << " Hz";
  }
}

// The control: floored at the whole impulse (as under the regularized law), the stop's residual
// sets the resting pile jittering and a step gains 5e-9 J at 250 Hz.
TEST(DropEnergy, UnderStickSlipALooserStopGains) {
  const ShippedFall f = RunShippedFall(250.0, true, true, 1.0);
  EXPECT_GT(f.largest_gain, kRoundOff * f.start_energy);
}

// Figures for docs/benchmarks.md: VISCERA_DROP_ENERGY_FIGURES=1 prints every rate.
TEST(DropEnergy, Figures) {
  if (!std::getenv("VISCERA_DROP_ENERGY_FIGURES"))
    GTEST_SKIP() << "set VISCERA_DROP_ENERGY_FIGURES=1 to print the table";
  for (double depth : {-1.0, 0.0}) {  // the scene's impact limiter, then none (and the linear law)
    for (double rate : {100.0, 250.0, 500.0, 1000.0}) {
      const FallRecord r = Drop(rate, depth, false);
      std::string gains;  // the steps that gained more than round-off
      for (size_t k = 0; k < r.energy.size(); ++k) {
        const double gain = r.energy[k] - (k ? r.energy[k - 1] : r.start_energy);
        if (gain > kRoundOff * r.start_energy) {
          // appended piece by piece: gcc 12's -Wrestrict misreads `" " + std::string&&` at -O3
          gains += ' ';
          gains += std::to_string(r.Seconds(static_cast<int>(k))).substr(0, 5);
          gains += " s (";
          gains += std::to_string(gain * 1e3).substr(0, 5);
          gains += " mJ)";
        }
      }
      std::printf("%s %5.0f Hz: gains at [%s]; %s\n",
                  depth < 0.0 ? "limiter alone" : "none         ", rate, gains.c_str(),
                  Describe(r).c_str());
    }
  }
}

}  // namespace
}  // namespace viscera::mechanics
