#pragma once
/// Plays a tool script the way a device driving a session does, resolving its rows aimed at the
/// tube. Such a row is resolved once, when its segment begins (at the tool's previous row's
/// time; at the start for a first row), against the tube as it is then, and stays there. The
/// hand then follows a path fixed before it moves, like a surgeon's reaching for a loop they
/// see. A target that kept chasing the tube it is moving would close a loop through the
/// simulation with one step of latency, and the force on the hand would depend on the rate
/// (docs/tool-coupling.md: 14 % RMS between 100 Hz and 1 kHz on the clearing gesture).
#include <map>
#include <string>
#include <vector>

#include "script/tool_script.h"

namespace viscera::script {

class ScriptPlayer {
 public:
  explicit ScriptPlayer(ToolScript script);

  const ToolScript& script() const { return script_; }
  /// The target of `tool` at t. The aims whose segments have begun by t are resolved against
  /// `tube` first; while its centre line is empty (no skeleton seen yet) they wait, and the
  /// row's written position stands in. Call with non-decreasing t. @pre script().Has(tool).
  ToolKeyframe At(const std::string& tool, double t, const Tube& tube);

 private:
  ToolScript script_;
  std::map<std::string, std::vector<ToolKeyframe>> frames_;  // aims resolved so far
  std::map<std::string, std::vector<bool>> pending_;         // rows still to aim
};

}  // namespace viscera::script
