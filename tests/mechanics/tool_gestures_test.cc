// Gestures other than the training task's on the clinical scene: every script of scenes/gestures
// (a hard press through the pile to the floor, fast sweeps, a grasp and yank, two tools at once)
// on scenes/cavity.toml at 100 Hz and 1 kHz. No pair, the tools' included, sinks deeper than 10 %
// of the radius at the end of any step. With the tools' contacts linear, the press and the sweeps
// sank a tool 39-53 % of R into the tube (docs/tool-coupling.md).
// The press and the sweeps test the tools' law (their deepest pair is the tool's); the grasping
// gestures test that a yanked or spread pile does not sink into its walls or itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "mechanics/step.h"
#include "scene/scene.h"
#include "script/scripted_tools.h"

namespace viscera::mechanics {
namespace {

struct GestureRun {
  double deepest = 0.0;  // fraction of R, any pair, at the end of any step
  double t = 0.0;
  std::string kind;         // what the deepest pair touches
  double peak_force = 0.0;  // N, the largest force on any hand
};

GestureRun RunGesture(const std::string& script_path, double rate_hz, double impact_depth = -1.0) {
  scene::Scene scene = scene::LoadSceneFile(VISCERA_SOURCE_DIR "/scenes/cavity.toml");
  scene::ChangeRate(&scene.model, rate_hz);
  if (impact_depth >= 0.0) scene.model.contacts.impact_depth = impact_depth;
  const Model model(scene.model);
  State state = InitialState(model);
  Workspace workspace(model);
  script::ScriptedTools scripted(model, script::ToolScript::Load(script_path), script_path);
  GestureRun run;
  const int steps = static_cast<int>(std::lround(scripted.duration() * rate_hz));
  for (int k = 0; k < steps; ++k) {
    Step(model, {{}, scripted.At(state.t + model.step_size(), workspace.interactions())}, &state,
         &workspace);
    const double depth = -state.contacts.min_clearance / model.params().radius;
    if (!std::isnan(depth) && depth > run.deepest)
      run.deepest = depth, run.t = state.t, run.kind = state.contacts.deepest;
    for (const ToolState& tool : state.tools)
      run.peak_force = std::max(run.peak_force, tool.force.norm());
  }
  EXPECT_EQ(state.nonfinite_resets, 0) << script_path;
  return run;
}

TEST(ToolGestures, NoGestureSinksAPairDeeperThanATenthOfTheRadius) {
  int scripts = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(VISCERA_SOURCE_DIR "/scenes/gestures")) {
    if (entry.path().extension() != ".csv") continue;
    ++scripts;
    for (const double rate : {100.0, 1000.0}) {
      const GestureRun r = RunGesture(entry.path().string(), rate);
      std::printf(
          "%-14s %6.0f Hz: deepest %.1f %% of R (%s pair, t = %.2f s), peak force on a hand %.2f "
          "N\n",
          entry.path().filename().c_str(), rate, 100.0 * r.deepest, r.kind.c_str(), r.t,
          r.peak_force);
      EXPECT_LE(r.deepest, 0.10) << entry.path().filename() << " at " << rate << " Hz: " << r.kind
                                 << " pair, t = " << r.t << " s";
      // the gesture works the tissue: a hand that felt under 1 N never pressed, swept or pulled
      EXPECT_GT(r.peak_force, 1.0) << entry.path().filename() << " at " << rate << " Hz";
    }
  }
  EXPECT_GE(scripts, 4);
}

// The control: the press with the contact law linear for every pair (impact_depth = 0, which also
// turns the impulses off) sinks far past a tenth of R, so the test above can fail.
TEST(ToolGestures, WithALinearLawThePressSinksDeep) {
  const GestureRun r = RunGesture(VISCERA_SOURCE_DIR "/scenes/gestures/press.csv", 1000.0, 0.0);
  EXPECT_GT(r.deepest, 0.2) << r.kind << " pair";
  EXPECT_EQ(r.kind, "tool");
}

}  // namespace
}  // namespace viscera::mechanics
