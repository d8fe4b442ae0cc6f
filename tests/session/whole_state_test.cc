// State is the whole state: a step reads nothing of its workspace's past. Mid-gesture on the
// cavity (the clearing gesture's grasp closed, the pile's self pairs in CG), a copy of the state
// steps bit for bit as the run it was copied from, in a fresh workspace and in one that ran on;
// a blow-up during the grasp, restored by the stepper or reset by the step, goes on as the
// restored state says, whatever the blown-up step left in the workspace.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "mechanics/step.h"
#include "scene/scene.h"
#include "script/scripted_tools.h"
#include "session/stepper.h"

namespace viscera::session {
namespace {

using mechanics::State;
using mechanics::ToolState;
using mechanics::ToolTarget;
using mechanics::Workspace;
using Targets = std::vector<ToolTarget>;

// Bit for bit, NaN and signed zeros included.
template <typename T>
bool SameBits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}
bool SameBits(const Points& a, const Points& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}
bool SameBits(const VecX& a, const VecX& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

bool SameTool(const ToolState& a, const ToolState& b) {
  return a.initialized == b.initialized && SameBits(a.tip, b.tip) &&
         SameBits(a.tip_velocity, b.tip_velocity) && SameBits(a.force, b.force) &&
         SameBits(a.torque, b.torque) && SameBits(a.stiffness, b.stiffness) &&
         SameBits(a.tissue_force, b.tissue_force) && SameBits(a.jaw, b.jaw) &&
         SameBits(a.coupling_scale, b.coupling_scale) && a.grasping == b.grasping &&
         SameBits(a.grasp_s, b.grasp_s) && SameBits(a.grasp_offset, b.grasp_offset) &&
         SameBits(a.grasp_scale, b.grasp_scale) && a.held_sphere == b.held_sphere &&
         a.clamped == b.clamped;
}

// q, q̇, the tools, the contacts and the warm start, bit for bit.
void ExpectSameState(const State& a, const State& b, const std::string& where) {
  EXPECT_TRUE(SameBits(a.q, b.q)) << where << ": q";
  EXPECT_TRUE(SameBits(a.qd, b.qd)) << where << ": qd";
  ASSERT_EQ(a.tools.size(), b.tools.size()) << where;
  for (size_t t = 0; t < a.tools.size(); ++t)
    EXPECT_TRUE(SameTool(a.tools[t], b.tools[t]))
        << where << ": tool " << t << ", force " << a.tools[t].force.transpose() << " / "
        << b.tools[t].force.transpose();
  EXPECT_EQ(a.contacts.self, b.contacts.self) << where;
  EXPECT_EQ(a.contacts.tool, b.contacts.tool) << where;
  EXPECT_TRUE(SameBits(a.contacts.min_clearance, b.contacts.min_clearance)) << where;
  EXPECT_EQ(a.substeps, b.substeps) << where;
  EXPECT_TRUE(SameBits(a.cg_correction, b.cg_correction)) << where << ": warm start";
  EXPECT_EQ(a.friction.size(), b.friction.size()) << where;
}

// The cavity driven by the clearing gesture at 100 Hz (the grasp closes at 1.5 s and holds until
// 4.5 s); every step's targets are kept, to drive other runs the same way.
struct Gesture {
  std::unique_ptr<const mechanics::Model> model;
  std::unique_ptr<Workspace> workspace;
  std::unique_ptr<script::ScriptedTools> scripted;
  State state;
  std::vector<Targets> targets;  // per step taken
  int hand = 0;                  // the tool the gesture drives

  explicit Gesture(double max_force_scale = 1.0) {
    scene::Scene scene = scene::LoadSceneFile(VISCERA_SOURCE_DIR "/scenes/cavity.toml");
    for (mechanics::ToolParams& tool : scene.model.tools) tool.max_force *= max_force_scale;
    model = std::make_unique<const mechanics::Model>(scene.model);
    workspace = std::make_unique<Workspace>(*model);
    state = mechanics::InitialState(*model);
    const script::ToolScript script =
        script::ToolScript::Load(VISCERA_SOURCE_DIR "/scenes/clearing.csv");
    scripted = std::make_unique<script::ScriptedTools>(*model, script);
    const auto& tools = model->params().tools;
    hand = static_cast<int>(
        std::find_if(tools.begin(), tools.end(),
                     [&](const mechanics::ToolParams& t) { return t.name == script.tools()[0]; }) -
        tools.begin());
  }
  // The next step's targets, as the gesture aims them from this run's workspace.
  Targets Next() {
    const auto span = scripted->At(state.t + model->step_size(), workspace->interactions());
    return Targets(span.begin(), span.end());
  }
  void Run(int steps) {
    for (int k = 0; k < steps; ++k) {
      targets.push_back(Next());
      mechanics::Step(*model, {{}, targets.back()}, &state, workspace.get());
    }
  }
};

constexpr int kMidGesture = 200;  // 2 s at 100 Hz: held, lifted off the lesion, in the pile
constexpr int kOnward = 30;

TEST(WholeState, ACopyMidGestureStepsTheSameInAFreshWorkspaceAndInAUsedOne) {
  Gesture g;
  g.Run(kMidGesture);
  ASSERT_TRUE(g.state.tools[g.hand].grasping) << "the grasp is closed";
  ASSERT_GT(g.state.contacts.self, 0) << "the pile presses on itself";
  ASSERT_EQ(g.state.nonfinite_resets, 0);
  const State copy = g.state;

  // The run goes on from the copy's state in the workspace that made it.
  std::vector<State> onward;
  bool coupled = false;
  for (int k = 0; k < kOnward; ++k) {
    g.Run(1);
    onward.push_back(g.state);
    coupled = coupled || g.state.cg_correction.squaredNorm() > 0.0;
  }
  EXPECT_TRUE(coupled) << "CG's warm start carried over some step";

  // The copy in a fresh workspace, and in the one that has run on past it.
  Workspace fresh(*g.model);
  State in_fresh = copy, in_used = copy;
  for (int k = 0; k < kOnward; ++k) {
    const Targets& targets = g.targets[kMidGesture + k];
    mechanics::Step(*g.model, {{}, targets}, &in_fresh, &fresh);
    mechanics::Step(*g.model, {{}, targets}, &in_used, g.workspace.get());
    ExpectSameState(in_fresh, onward[k], "fresh workspace, step " + std::to_string(k));
    ExpectSameState(in_used, onward[k], "used workspace, step " + std::to_string(k));
    if (HasFailure()) return;
  }
  EXPECT_TRUE(in_used.tools[g.hand].grasping);
}

// Steps `steps` of the gesture's targets from `from`, in `stepper` and, from a copy of its state,
// in a fresh workspace: the same states, bit for bit.
void ExpectStepperFollowsItsState(const Gesture& g, int from, int steps, Stepper* stepper) {
  Workspace fresh(*g.model);
  State copy = stepper->state();
  for (int k = 0; k < steps; ++k) {
    const Targets& targets = g.targets[from + k];
    EXPECT_FALSE(stepper->Advance(targets));
    mechanics::Step(*g.model, {{}, targets}, &copy, &fresh);
    ExpectSameState(stepper->state(), copy, "after the restore, step " + std::to_string(k));
    if (::testing::Test::HasFailure()) return;
  }
}

// A target thrown hundreds of metres away with the hand's force clamp lifted: the grasped tube is
// pulled away faster than Stepper::kMaxSpeed (a runaway), and the stepper restores its last good
// state, mid-grasp. The grasp goes on as that state has it (not as the blown-up step left the
// workspace), and so do the warm start and the broad phase's list.
TEST(WholeState, ABlowUpDuringAGraspRestoresTheGraspTheRestoredStateHolds) {
  Gesture g(/*max_force_scale=*/1e9);
  g.Run(kMidGesture + kOnward);
  ASSERT_TRUE(g.state.tools[g.hand].grasping);
  Stepper stepper(*g.model);
  for (int k = 0; k < kMidGesture; ++k) ASSERT_FALSE(stepper.Advance(g.targets[k]));
  const State good = stepper.state();  // saved as the last good state (every 10 steps)
  ASSERT_EQ(good.steps % Stepper::kGoodEvery, 0);
  ASSERT_TRUE(good.tools[g.hand].grasping);

  // How far a throw must go to run away depends on the pile: farther until one does, within the
  // steps before the next good state is saved.
  bool blew_up = false;
  for (double distance = 100.0; !blew_up && distance < 2000.0; distance *= 2.0) {
    Targets thrown = g.targets[kMidGesture];
    thrown[g.hand].tip += Vec3(distance, 0.0, 0.0);
    blew_up = stepper.Advance(thrown);
  }
  ASSERT_TRUE(blew_up) << "a throw ran away";
  ASSERT_LT(stepper.state().steps, kMidGesture + Stepper::kGoodEvery);
  const State& restored = stepper.state();
  EXPECT_TRUE(SameBits(restored.q, good.q));
  EXPECT_TRUE(SameTool(restored.tools[g.hand], good.tools[g.hand]));
  EXPECT_TRUE(SameBits(restored.cg_correction, good.cg_correction));
  EXPECT_EQ(restored.broad_phase.stamp, good.broad_phase.stamp);
  ExpectStepperFollowsItsState(g, kMidGesture, kOnward, &stepper);
  EXPECT_TRUE(stepper.state().tools[g.hand].grasping) << "still held";
}

// A step whose result is not finite (a NaN injected mid-grasp) resets the whole state: the grasp
// is gone from it, and from the workspace too, which then steps as a fresh one.
TEST(WholeState, ANonFiniteStepDuringAGraspResetsTheGraspWithTheState) {
  Gesture g;
  g.Run(kMidGesture);
  ASSERT_TRUE(g.state.tools[g.hand].grasping);
  g.state.qd(7, 2) = std::nan("");
  g.Run(1);
  ASSERT_EQ(g.state.nonfinite_resets, 1);
  for (const ToolState& t : g.state.tools) {
    EXPECT_FALSE(t.grasping);
    EXPECT_EQ(t.held_sphere, -1);
  }
  EXPECT_EQ(g.state.cg_correction.squaredNorm(), 0.0);
  Workspace fresh(*g.model);
  State copy = g.state;
  for (int k = 0; k < kOnward; ++k) {
    g.Run(1);
    mechanics::Step(*g.model, {{}, g.targets.back()}, &copy, &fresh);
    ExpectSameState(g.state, copy, "after the reset, step " + std::to_string(k));
    if (HasFailure()) return;
  }
}

}  // namespace
}  // namespace viscera::session
