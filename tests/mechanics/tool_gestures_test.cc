// Gestures other than the training task's on the clinical scene: every script of scenes/gestures
// (a hard press through the pile to the floor, fast sweeps, a grasp and yank, two tools at once)
// on scenes/cavity.toml at 100 Hz and 1 kHz. No pair, the tools' included, sinks deeper than 10 %
// of the radius at the end of any step. Until session 8 the tools' contacts were linear: the press
// and the sweeps sank a tool 39-53 % of R into the tube (docs/contacts.md, "Tools and haptics").
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "mechanics/step.h"
#include "scene/scene.h"
#include "script/scripted_tools.h"

namespace viscera::mechanics {
namespace {

struct Deepest {
  double depth = 0.0;  // fraction of R
  double t = 0.0;
  std::string kind;
};

Deepest RunGesture(const std::string& script_path, double rate_hz) {
  scene::Scene scene = scene::LoadSceneFile(VISCERA_SOURCE_DIR "/scenes/cavity.toml");
  scene::ChangeRate(&scene.model, rate_hz);
  const Model model(scene.model);
  State state = InitialState(model);
  Workspace workspace(model);
  script::ScriptedTools scripted(model, script::ToolScript::Load(script_path), script_path);
  Deepest deepest;
  const int steps = static_cast<int>(std::lround(scripted.duration() * rate_hz));
  for (int k = 0; k < steps; ++k) {
    Step(model, {{}, scripted.At(state.t + model.step_size(), workspace.interactions())}, &state, &workspace);
    const double depth = -state.contacts.min_clearance / model.params().radius;
    if (!std::isnan(depth) && depth > deepest.depth) deepest = {depth, state.t, state.contacts.deepest};
  }
  EXPECT_EQ(state.nonfinite_resets, 0) << script_path;
  return deepest;
}

TEST(ToolGestures, NoGestureSinksAPairDeeperThanATenthOfTheRadius) {
  int scripts = 0;
  for (const auto& entry : std::filesystem::directory_iterator(VISCERA_SOURCE_DIR "/scenes/gestures")) {
    if (entry.path().extension() != ".csv") continue;
    ++scripts;
    for (const double rate : {100.0, 1000.0}) {
      const Deepest d = RunGesture(entry.path().string(), rate);
      EXPECT_LE(d.depth, 0.10) << entry.path().filename() << " at " << rate << " Hz: " << d.kind << " pair, t = " << d.t << " s";
    }
  }
  EXPECT_GE(scripts, 4);
}

}  // namespace
}  // namespace viscera::mechanics
