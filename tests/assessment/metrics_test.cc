// The assessment's per-step metrics: closed forms on synthetic steps (path length of a polygon
// inscribed in a circle, force quantiles of a known distribution, traction events, grasps and
// regrasps, organ contacts), then a scripted gesture through the real mechanics with known pulls.
#include <gtest/gtest.h>

#include <cstdio>

#include <cmath>
#include <numbers>

#include "assessment/metrics.h"
#include "mechanics/step.h"
#include "scene/scene.h"
#include "tests/mechanics/table_scene.h"

namespace viscera::assessment {
namespace {

using mechanics::ModelParams;
using mechanics::State;

// One tool, no intestine needed for the synthetic steps (the metrics read the tools only), and
// a sphere organ at (1, 0, 0) of radius 0.1.
ModelParams OneTool() {
  ModelParams p;
  mechanics::ToolParams t;
  t.name = "left";
  t.radius = 0.0025;
  p.tools.push_back(t);
  collision::Obstacle organ;
  organ.kind = collision::ObstacleKind::kSphere;
  organ.name = "bladder";
  organ.centre = Vec3(1.0, 0.0, 0.0);
  organ.radius = 0.1;
  p.obstacles.push_back(organ);
  return p;
}

State Tip(const Vec3& tip, double force = 0.0, bool grasping = false) {
  State s;
  s.tools.resize(1);
  s.tools[0].initialized = true;
  s.tools[0].target.active = true;
  s.tools[0].tip = tip;
  s.tools[0].tissue_force = Vec3(0.0, 0.0, force);
  s.tools[0].grasping = grasping;
  return s;
}

Report Measure(const ModelParams& p, const std::vector<State>& steps, double dt) {
  SessionMetrics m(p);
  for (const State& s : steps) m.AddStep(s, dt);
  Report r;
  m.Fill(&r);
  return r;
}

TEST(SessionMetrics, PathLengthOfAnInscribedPolygonIsItsPerimeter) {
  // N steps around a circle of radius R: the tip's path is the regular N-gon, 2 N R sin(pi / N)
  const double radius = 0.05;
  for (const int n : {4, 7, 100, 1000}) {
    std::vector<State> steps;
    for (int k = 0; k <= n; ++k) {
      const double a = 2.0 * std::numbers::pi * k / n;
      steps.push_back(Tip(Vec3(radius * std::cos(a), radius * std::sin(a), 0.3)));
    }
    const Report r = Measure(OneTool(), steps, 0.01);
    EXPECT_NEAR(r.tools[0].path_length, 2.0 * n * radius * std::sin(std::numbers::pi / n), 1e-12)
        << n;
    EXPECT_NEAR(r.tools[0].active_time, 0.01 * (n + 1), 1e-12);
  }
}

TEST(SessionMetrics, AToolThatNeverHadATargetTravelsNothing) {
  State s = Tip(Vec3(0.0, 0.0, 0.3));
  s.tools[0].initialized = false;
  std::vector<State> steps{s, s};
  steps[1].tools[0].tip = Vec3(1.0, 0.0, 0.0);  // the port would be elsewhere: not counted
  EXPECT_EQ(Measure(OneTool(), steps, 0.01).tools[0].path_length, 0.0);
}

TEST(SessionMetrics, ForceQuantilesOverTheContactStepsWithinHalfABin) {
  // 2000 contact steps with forces 0.001 .. 2.000 N, and 500 steps without contact (not counted)
  std::vector<State> steps;
  for (int k = 1; k <= 2000; ++k) steps.push_back(Tip(Vec3::Zero(), 0.001 * k));
  for (int k = 0; k < 500; ++k) steps.push_back(Tip(Vec3::Zero(), 0.0));
  const Report r = Measure(OneTool(), steps, 0.001);
  const double half_bin = 0.5 * ForceHistogram::kForceBin;
  EXPECT_NEAR(r.tools[0].force_p50, 1.000, half_bin + 1e-12);  // nearest rank: the 1000th
  EXPECT_NEAR(r.tools[0].force_p95, 1.900, half_bin + 1e-12);
  EXPECT_DOUBLE_EQ(r.tools[0].force_max, 2.000);
  EXPECT_NEAR(r.tools[0].contact_time, 2.0, 1e-9);
}

TEST(SessionMetrics, TractionEventsAreExcursionsAboveTheForceHeldForTheHoldTime) {
  ModelParams p = OneTool();
  p.task.assessment.traction_force = 3.0;
  p.task.assessment.traction_hold = 0.5;
  const double dt = 0.01;
  std::vector<State> steps;
  auto phase = [&](double force, double seconds) {
    for (int k = 0; k < static_cast<int>(std::lround(seconds / dt)); ++k)
      steps.push_back(Tip(Vec3::Zero(), force));
  };
  phase(4.0, 0.70);  // event 1
  phase(1.0, 0.20);
  phase(4.0, 0.49);  // too short
  phase(2.9, 0.10);
  phase(3.0, 1.00);  // not above
  phase(3.5, 0.50);  // exactly the hold: event 2
  phase(0.0, 0.10);
  phase(9.0, 2.00);  // one long excursion is one event: event 3
  const Report r = Measure(p, steps, dt);
  EXPECT_EQ(r.tools[0].traction_events, 3);
  EXPECT_NEAR(r.tools[0].traction_time, 0.70 + 0.49 + 0.50 + 2.00, 1e-9);
  EXPECT_DOUBLE_EQ(r.tools[0].force_max, 9.0);
}

TEST(SessionMetrics, GraspsAndRegraspsWithinTheWindow) {
  ModelParams p = OneTool();
  p.task.assessment.regrasp_window = 1.0;
  const double dt = 0.01;
  std::vector<State> steps;
  auto phase = [&](bool grasping, double seconds) {
    for (int k = 0; k < static_cast<int>(std::lround(seconds / dt)); ++k)
      steps.push_back(Tip(Vec3::Zero(), 1.0, grasping));
  };
  phase(false, 0.5);
  phase(true, 1.0);  // grasp 1
  phase(false, 0.5);
  phase(true, 1.0);  // grasp 2, a regrasp (0.5 s after the release)
  phase(false, 2.0);
  phase(true, 0.3);  // grasp 3 (2 s after: a new grasp)
  phase(false, 1.0);
  phase(true, 0.3);  // grasp 4, a regrasp (exactly the window)
  const Report r = Measure(p, steps, dt);
  EXPECT_EQ(r.tools[0].grasps, 4);
  EXPECT_EQ(r.tools[0].regrasps, 2);
}

TEST(SessionMetrics, OrganContactsCountTheJawsEnteringAnOrgan) {
  const double dt = 0.01;
  std::vector<State> steps;
  auto at = [&](double x, int n) {
    for (int k = 0; k < n; ++k) steps.push_back(Tip(Vec3(x, 0.0, 0.0)));
  };
  at(0.5, 10);
  at(0.9, 5);     // on the surface: contact 1
  at(0.89, 5);    // 10 mm off: clear
  at(0.8980, 3);  // 2 mm off, within the jaws' 2.5 mm radius: contact 2
  at(0.8970, 3);  // 3 mm off: clear
  at(0.95, 4);    // inside: contact 3
  const Report r = Measure(OneTool(), steps, dt);
  EXPECT_EQ(r.tools[0].organ_contacts, 3);
  EXPECT_NEAR(r.tools[0].organ_contact_time, dt * (5 + 3 + 4), 1e-9);
}

// The real mechanics: the grasper of tests/mechanics/tools_test.cc's table scene grasps the
// tube's middle and pulls it up with known pulls: a hard one (the target 20 cm up: about 3.4 N
// at rest, above this scene's 2 N traction force) held 2 s, twice; a soft one (2 cm: 0.3 N) held
// 1 s; a hard one gone again at once. The tip is light and its weight not simulated, so at rest
// the force on the tissue equals the hand's pull.
const std::string kTable = std::string(viscera::testing::kTableScene) + R"(
[assessment]
traction_force = 2.0
traction_hold = 0.5
regrasp_window = 1.0
)";
TEST(SessionMetrics, ScriptedPullsThroughTheMechanics) {
  const mechanics::Model model(scene::ParseScene(kTable).model);
  State state = mechanics::InitialState(model);
  mechanics::Workspace workspace(model);
  SessionMetrics metrics(model.params());
  // The jaws close where they touch the tube's top (z = 2R, plus the tool's radius): pressed
  // down to its axis they pressed it into the table, the largest force of the run (4.2 N).
  const Vec3 grasp(0.3, 0.0, 0.0275);
  mechanics::ToolTarget target;
  target.tip = grasp + Vec3(0.0, 0.0, 0.05);  // the jaws start above the tube
  double max_pull = 0.0, rest_error = 0.0;
  // the hand moves the target in a straight line to `to` over `ramp` seconds (no jumps: a
  // released pull would slam the tube into the table), then holds it for `hold` seconds
  auto move = [&](const Vec3& to, double jaw, double ramp, double hold, bool pulling_hard = false) {
    const Vec3 from = target.tip;
    target.jaw = jaw;
    const int ramp_steps = static_cast<int>(std::lround(ramp * model.params().rate_hz));
    const int steps = ramp_steps + static_cast<int>(std::lround(hold * model.params().rate_hz));
    for (int k = 1; k <= steps; ++k) {
      target.tip =
          k < ramp_steps ? Vec3(from + (to - from) * (static_cast<double>(k) / ramp_steps)) : to;
      mechanics::Step(model, {{}, std::span<const mechanics::ToolTarget>(&target, 1)}, &state,
                      &workspace);
      metrics.AddStep(state, model.step_size());
    }
    if (pulling_hard) {
      // at rest, action and reaction through the tip: the tissue feels the hand's pull
      max_pull = std::max(max_pull, state.tools[0].force.norm());
      rest_error = std::max(
          rest_error, std::abs(state.tools[0].tissue_force.norm() - state.tools[0].force.norm()));
    }
  };
  const Vec3 hard = grasp + Vec3(0.0, 0.0, 0.20), soft = grasp + Vec3(0.0, 0.0, 0.02);
  move(grasp, 1.0, 0.3, 0.3);       // the open jaws come down on the tube
  move(grasp, 0.0, 0.0, 0.3);       // grasp 1
  move(hard, 0.0, 1.0, 2.0, true);  // traction event 1
  move(grasp, 0.0, 1.0, 0.5);
  move(soft, 0.0, 0.3, 1.0);  // far below the threshold
  move(grasp, 0.0, 0.3, 0.3);
  move(hard, 0.0, 0.6, 0.0);  // up and straight back down: above it too briefly
  move(grasp, 0.0, 0.6, 0.5);
  move(grasp, 1.0, 0.0, 0.4);       // release ...
  move(grasp, 0.0, 0.0, 0.3);       // ... and grasp again within 1 s: grasp 2, a regrasp
  move(hard, 0.0, 1.0, 2.0, true);  // traction event 2
  move(grasp, 0.0, 1.0, 0.5);
  move(grasp, 1.0, 0.0, 0.5);
  EXPECT_EQ(state.nonfinite_resets, 0);

  Report r;
  metrics.Fill(&r);
  const ToolReport& t = r.tools[0];
  // the hard pull holds the tube 20 cm up with about 3.4 N, well inside the device's 5 N
  EXPECT_GT(max_pull, 3.0);
  EXPECT_LT(max_pull, 5.0);
  EXPECT_LT(rest_error, 0.01 * max_pull) << "tissue force = hand force at rest";
  // the largest tissue force is the pull's, plus what the ramps overshoot (< 20 %)
  EXPECT_GE(t.force_max, max_pull);
  EXPECT_LT(t.force_max, 1.2 * max_pull);
  EXPECT_EQ(t.traction_events, 2);
  EXPECT_EQ(t.grasps, 2);
  EXPECT_EQ(t.regrasps, 1);
  // The path: the hand's is 5 cm down, 20 cm up and back three times, 2 cm up and back once. The
  // tip follows it but stops short of the top of each hard pull by the coupling's stretch
  // (pull / stiffness, 11 mm), on the way up and back: its path lies between the two.
  const double hand_path = 0.05 + 6 * 0.20 + 2 * 0.02;
  const double short_of_top = max_pull / model.params().tools[0].coupling_stiffness;
  std::printf("path: tip %.4f m, hand %.4f m, stretch at the top %.4f m\n", t.path_length,
              hand_path, short_of_top);
  EXPECT_LT(t.path_length, hand_path);
  EXPECT_GT(t.path_length, hand_path - 3 * 2 * short_of_top);
}

// A tool in free space following a square: the tip's path is the square's perimeter (the
// coupling rounds the corners and overshoots a little: within 2 %).
TEST(SessionMetrics, FreeToolPathFollowsTheHand) {
  const mechanics::Model model(scene::ParseScene(kTable).model);
  State state = mechanics::InitialState(model);
  mechanics::Workspace workspace(model);
  SessionMetrics metrics(model.params());
  const double side = 0.04, z = 0.15, seconds_per_side = 1.0;
  const std::vector<Vec3> corners{
      {0.28, -0.02, z}, {0.32, -0.02, z}, {0.32, 0.02, z}, {0.28, 0.02, z}, {0.28, -0.02, z}};
  mechanics::ToolTarget target;
  target.tip = corners[0];
  auto step = [&] {
    mechanics::Step(model, {{}, std::span<const mechanics::ToolTarget>(&target, 1)}, &state,
                    &workspace);
  };
  for (int k = 0; k < 100; ++k) step();  // settle at the first corner, not measured
  const int per_side = static_cast<int>(seconds_per_side * model.params().rate_hz);
  for (size_t c = 0; c + 1 < corners.size(); ++c) {
    for (int k = 1; k <= per_side; ++k) {
      target.tip = corners[c] + (corners[c + 1] - corners[c]) * (static_cast<double>(k) / per_side);
      step();
      metrics.AddStep(state, model.step_size());
    }
  }
  for (int k = 0; k < 100; ++k) {
    step();
    metrics.AddStep(state, model.step_size());
  }
  Report r;
  metrics.Fill(&r);
  EXPECT_NEAR(r.tools[0].path_length, 4.0 * side, 0.02 * 4.0 * side);
  EXPECT_EQ(r.tools[0].contact_time, 0.0) << "free space: no tissue force";
}

}  // namespace
}  // namespace viscera::assessment
