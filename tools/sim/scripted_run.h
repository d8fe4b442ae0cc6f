#pragma once
// A scene stepped as viscera-sim steps it: the model's start, its workspace, the tool script's
// targets (tools the script does not name stay idle; without a script, all do), and the sphere
// chain placed for the start before the first step (the first frame shows it). viscera-sim and
// viscera-state-digest share it, so a digest checks the very run viscera-sim makes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "mechanics/step.h"
#include "script/scripted_tools.h"

namespace viscera::tools {

class ScriptedRun {
 public:
  /// @pre model outlives the run. @throws InputError for a script the model cannot play.
  ScriptedRun(const mechanics::Model& model, const std::string& tool_script)
      : model_(model), state_(mechanics::InitialState(model)), workspace_(model) {
    if (!tool_script.empty())
      scripted_.emplace(model, script::ToolScript::Load(tool_script), tool_script);
    if (interactions() != nullptr) interactions()->BeginSubstep(TargetsAt(0.0), 0.0, &state_);
  }

  /// The tools' targets for the next step (the script at the step's end).
  std::span<const mechanics::ToolTarget> NextTargets() {
    return TargetsAt(state_.t + model_.step_size());
  }
  void Step(std::span<const mechanics::ToolTarget> targets) {
    mechanics::Step(model_, {{}, targets}, &state_, &workspace_);
  }
  /// Steps that cover `duration` simulated seconds at the model's rate (at least one).
  int64_t StepsFor(double duration) const {
    return std::max<int64_t>(1, std::llround(duration * model_.params().rate_hz));
  }

  const mechanics::State& state() const { return state_; }
  /// The script's grasp rows reached again, and how far they set it behind the clock (s).
  int script_reaches() const { return scripted_ ? scripted_->player().reaches() : 0; }
  double script_delay() const { return scripted_ ? scripted_->delay() : 0.0; }
  mechanics::Interactions* interactions() { return workspace_.interactions(); }
  const mechanics::Integrator& integrator() { return workspace_.integrator(); }

 private:
  std::span<const mechanics::ToolTarget> TargetsAt(double t) {
    return scripted_ ? scripted_->At(t, interactions(), &state_)
                     : std::span<const mechanics::ToolTarget>{};
  }

  const mechanics::Model& model_;
  mechanics::State state_;
  mechanics::Workspace workspace_;
  std::optional<script::ScriptedTools> scripted_;
};

}  // namespace viscera::tools
