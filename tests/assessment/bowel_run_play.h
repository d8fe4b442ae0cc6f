#pragma once
// Plays scenes/bowel_run.toml's scripted runs offline, scored step by step as a session is
// (tests/assessment/bowel_run_test.cc, bowel_run_1khz_test.cc).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "assessment/running.h"
#include "mechanics/step.h"
#include "scene/scene.h"
#include "script/camera_script.h"
#include "script/scripted_tools.h"
#include "script/tool_script.h"

namespace viscera::assessment::bowel_run {

struct Played {
  RunningReport report;
  std::vector<double> grasps;  // where each grasp took the bowel (curve parameter), in order
  std::set<int> aimed;         // the segments the played rows aimed at (aim = tube@S)
  std::set<int> shut;          // ... of them, those the jaws closed on shut (jaw 0)
  std::vector<char> covered;   // per segment
  int last_segment = -1;       // the segment of the last grasp
  int64_t nonfinite_resets = 0;
};

// The scene, settled once (its 9 s settle is the costly part of loading it).
inline const scene::Scene& BowelRunScene() {
  static const scene::Scene scene =
      scene::LoadSceneFile(VISCERA_SOURCE_DIR "/scenes/bowel_run.toml");
  return scene;
}

// Plays the first `seconds` of scenes/bowel_run_<kind>.csv at `rate_hz`, judged through the
// scope its camera script moves (bowel_run_<kind>_camera.csv). The novices are played for their
// first grasps only, past the ones that tell.
inline Played Play(const std::string& kind, double seconds, double rate_hz) {
  scene::Scene scene = BowelRunScene();
  scene::ChangeRate(&scene.model, rate_hz);
  const mechanics::Model model(scene.model);
  const std::string file = VISCERA_SOURCE_DIR "/scenes/bowel_run_" + kind + ".csv";
  const script::ToolScript script = script::ToolScript::Load(file);
  RunningScore score(model.params());
  const script::CameraScript camera =
      script::CameraScript::Load(VISCERA_SOURCE_DIR "/scenes/bowel_run_" + kind + "_camera.csv");
  auto view_at = [&](double t) {
    const mechanics::ScopeParams& scope = model.params().scope.value();
    const script::CameraKeyframe k = camera.At(t);
    return View{k.eye, k.target, scope.up, scope.fov_deg, 640.0 / 480.0};
  };
  Played run;
  const TissueDamage& damage = score.damage();
  for (const std::string& tool : script.tools()) {
    const std::vector<script::ToolKeyframe>& rows = script.frames(tool);
    for (size_t i = 0; i + 1 < rows.size(); ++i) {
      // the part grasped: the last row aimed at the tube before the row closing the jaws
      if (rows[i].t > seconds || std::isnan(rows[i].along) || rows[i + 1].at_tube) continue;
      run.aimed.insert(damage.SegmentOf(rows[i].along));
      if (rows[i + 1].jaw == 0.0) run.shut.insert(damage.SegmentOf(rows[i].along));
    }
  }
  mechanics::State state = mechanics::InitialState(model);
  mechanics::Workspace workspace(model);
  script::ScriptedTools tools(model, script, file);
  std::vector<bool> holding(model.params().tools.size(), false);
  const int steps = static_cast<int>(std::lround(seconds * model.params().rate_hz));
  for (int k = 0; k < steps; ++k) {
    const auto targets = tools.At(state.t + model.step_size(), workspace.interactions());
    mechanics::Step(model, {{}, targets}, &state, &workspace);
    score.SetView(view_at(state.t));
    score.AddStep(state, model.step_size());
    for (size_t i = 0; i < holding.size(); ++i) {
      const mechanics::ToolState& ts = state.tools[i];
      const bool now = ts.grasping && !ts.slipped;
      if (now && !holding[i]) run.grasps.push_back(ts.grasp_s);
      holding[i] = now;
    }
  }
  score.Fill(&run.report);
  run.covered = score.covered();
  if (!run.grasps.empty()) run.last_segment = damage.SegmentOf(run.grasps.back());
  run.nonfinite_resets = state.nonfinite_resets;
  return run;
}

// Every segment from the flexure to the last grasp was between the jaws, grasped in order
// (never back along the bowel), with no damage event and no slip.
inline void ExpectCoveredInOrderUnhurt(const Played& run, int at_least) {
  ASSERT_EQ(run.nonfinite_resets, 0);
  ASSERT_GE(run.last_segment, at_least) << "the run reached segment " << run.last_segment;
  for (int k = 0; k <= run.last_segment; ++k)
    EXPECT_TRUE(run.covered[static_cast<size_t>(k)]) << "segment " << k << " was missed";
  for (size_t k = 1; k < run.grasps.size(); ++k)
    EXPECT_GT(run.grasps[k], run.grasps[k - 1]) << "grasp " << k << " went back along the bowel";
  EXPECT_EQ(run.report.reversals, 0);
  EXPECT_EQ(run.report.regrasps, 0);
  EXPECT_EQ(run.report.slips, 0);
  EXPECT_TRUE(run.report.events.empty())
      << run.report.events.front().kind << " at " << run.report.events.front().segment;
}

}  // namespace viscera::assessment::bowel_run
