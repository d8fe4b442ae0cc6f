#include "script/scripted_tools.h"

#include <utility>

#include "common/check.h"

namespace viscera::script {

ScriptedTools::ScriptedTools(const mechanics::Model& model, ToolScript script,
                             const std::string& source)
    : model_(model), player_(std::move(script)), targets_(model.params().tools.size()) {
  for (const std::string& name : player_.script().tools()) {
    bool known = false;
    for (const mechanics::ToolParams& t : model.params().tools) known = known || t.name == name;
    ThrowUnless(known, source, ": tool \"", name, "\" is not in the scene (its [[tool]] names it)");
  }
}

std::span<const mechanics::ToolTarget> ScriptedTools::At(
    double t, const mechanics::Interactions* interactions, const mechanics::State* state) {
  tube_.centre_line.clear();
  if (player_.script().aims_at_tube() && interactions) {
    for (const collision::Sphere& s : interactions->chain().spheres())
      tube_.centre_line.push_back(s.centre);
    tube_.radius = interactions->chain().radius();
  }
  for (size_t i = 0; i < targets_.size(); ++i) {
    const std::string& name = model_.params().tools[i].name;
    mechanics::ToolTarget& target = targets_[i];
    target.active = player_.script().Has(name);
    if (!target.active) continue;
    const bool seen = state != nullptr && i < state->tools.size() && state->tools[i].initialized;
    const ToolKeyframe k = player_.At(name, t, tube_, seen ? &state->tools[i].tip : nullptr);
    target.tip = k.tip;
    target.orientation = k.orientation;
    target.jaw = k.jaw;
  }
  return targets_;
}

}  // namespace viscera::script
