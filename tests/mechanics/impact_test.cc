// Impacts: the coil of scenes/fall.toml dropped from 50 cm (it ships at ~5 cm), at every rate
// a session may ask for. Measured by the deepest pair at the end of every step and the energy
// of every step (no input after the release). Issue 10 asks for 10 % of the radius; the impact
// limiter and the stiffening law reach 12-17 % (from 65-82 %), see docs/contacts.md, "Impacts":
// the bound below guards that, and the negative control shows what the limiter is worth.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "mechanics/step.h"
#include "scene/scene.h"

namespace viscera::mechanics {
namespace {

struct Drop {
  double height = 0.5;       // m: the centre line's lowest point above the plane at release
  double rate_hz = 100.0;
  IntegratorKind integrator = IntegratorKind::kImplicitEuler;
  double impact_depth = -1;  // < 0: the default
  double bend_stiffness = -1;  // < 0: the scene's
  double seconds = 0.8;
};

struct DropRun {
  double deepest = 0.0;  // fraction of the radius, deepest pair at the end of any step
  double growth = 0.0;   // J, the largest energy gain of one step
  double start = 0.0;    // J, the energy at release
  double end = 0.0;      // J, at the end
  int substeps = 0;      // in all
};

DropRun RunDrop(const Drop& d) {
  ModelParams p = scene::LoadSceneFile(VISCERA_SOURCE_DIR "/scenes/fall.toml").model;
  p.integrator = d.integrator;
  scene::ChangeRate(&p, d.rate_hz);
  if (d.impact_depth >= 0.0) p.contacts.impact_depth = d.impact_depth;
  if (d.bend_stiffness >= 0.0) p.bend_stiffness = d.bend_stiffness;
  const double lowest = p.initial_q.col(2).minCoeff();
  p.initial_q.col(2).array() += d.height - lowest;
  const Model model(p);
  State state = InitialState(model);
  Workspace workspace(model);
  Interactions* in = workspace.interactions();
  DropRun run;
  run.start = ComputeEnergies(model, state.q, state.qd, in).total();
  double previous = run.start;
  const int steps = static_cast<int>(std::lround(d.seconds * d.rate_hz));
  for (int k = 0; k < steps; ++k) {
    Step(model, {}, &state, &workspace);
    run.substeps += state.substeps;
    if (!std::isnan(state.contacts.min_clearance)) run.deepest = std::max(run.deepest, -state.contacts.min_clearance / p.radius);
    const double e = ComputeEnergies(model, state.q, state.qd, in).total();
    run.growth = std::max(run.growth, e - previous);
    previous = e;
  }
  run.end = previous;
  return run;
}

const char* Name(IntegratorKind kind) { return kind == IntegratorKind::kRk4 ? "rk4" : "implicit"; }

class FiftyCentimetreDrop : public testing::TestWithParam<double> {};

TEST_P(FiftyCentimetreDrop, SinksLessThanAFifthOfTheRadiusAndNeverGainsEnergy) {
  Drop d;
  d.rate_hz = GetParam();
  const DropRun run = RunDrop(d);
  EXPECT_LE(run.deepest, 0.20) << d.rate_hz << " Hz";  // the goal is 0.10: not met yet
  // 1 kHz gains 3e-3 J in one step after the impact (the stiffening law, linearized once per
  // sub-step): a known defect, docs/contacts.md.
  if (d.rate_hz < 1000.0) EXPECT_LE(run.growth, 1e-6 * run.start) << d.rate_hz << " Hz";
  EXPECT_LT(run.end, 0.5 * run.start);  // it landed and the impact dissipated
}

INSTANTIATE_TEST_SUITE_P(Rates, FiftyCentimetreDrop, testing::Values(100.0, 250.0, 500.0, 1000.0));

// The negative control: the same drop with the limiter off sinks far beyond 10 % (the penalty
// alone cannot stop a 3 m/s landing within 1.25 mm), so the test above measures the limiter.
TEST(Impacts, WithoutTheLimiterTheDropSinksDeep) {
  Drop d;
  d.impact_depth = 0.0;  // no limiter, and the law stays linear
  const DropRun run = RunDrop(d);
  EXPECT_GT(run.deepest, 0.5);
  EXPECT_GT(run.deepest, 3.0 * RunDrop(Drop{}).deepest);
}

// Figures for docs/contacts.md: VISCERA_IMPACT_FIGURES=1 prints every candidate at every rate.
TEST(Impacts, Figures) {
  if (!std::getenv("VISCERA_IMPACT_FIGURES")) GTEST_SKIP() << "set VISCERA_IMPACT_FIGURES=1 to print the table";
  const char* only = std::getenv("VISCERA_IMPACT_ONLY");  // "height rate": one run
  if (only) {
    Drop d;
    std::sscanf(only, "%lf %lf %lf", &d.height, &d.rate_hz, &d.impact_depth);
    const DropRun r = RunDrop(d);
    std::printf("deepest %.1f %% R growth %.2e substeps %d\n", 100 * r.deepest, r.growth, r.substeps);
    return;
  }
  for (double height : {0.3, 0.5, 1.0}) {
    for (IntegratorKind kind : {IntegratorKind::kImplicitEuler, IntegratorKind::kRk4}) {
      if (kind == IntegratorKind::kRk4 && height != 0.5) continue;
      for (double depth : {0.0, 0.05}) {
        for (double rate : {100.0, 250.0, 500.0, 1000.0}) {
          Drop d{height, rate, kind, depth};
          const DropRun r = RunDrop(d);
          std::printf("height %.2f %-8s limiter %.2f %5.0f Hz: deepest %6.1f %% R, worst step energy gain %+.2e J, "
                      "energy %.3f -> %.3f J, %d sub-steps\n",
                      height, Name(kind), depth, rate, 100.0 * r.deepest, r.growth, r.start, r.end, r.substeps);
        }
      }
    }
  }
}

}  // namespace
}  // namespace viscera::mechanics
