#include "script/script_player.h"

#include <utility>

namespace viscera::script {

ScriptPlayer::ScriptPlayer(ToolScript script) : script_(std::move(script)) {
  for (const std::string& tool : script_.tools()) {
    const std::vector<ToolKeyframe>& f = script_.frames(tool);
    frames_[tool] = f;
    std::vector<bool>& pending = pending_[tool];
    for (const ToolKeyframe& k : f) pending.push_back(k.at_tube || k.offset);
  }
}

ToolKeyframe ScriptPlayer::At(const std::string& tool, double t, const Tube& tube) {
  std::vector<ToolKeyframe>& f = frames_.at(tool);
  std::vector<bool>& pending = pending_.at(tool);
  if (!tube.centre_line.empty()) {
    for (size_t i = 0; i < f.size(); ++i) {
      const bool begun = i == 0 || t >= f[i - 1].t;
      if (!begun) break;
      if (!pending[i]) continue;
      const ToolKeyframe& row = script_.frames(tool)[i];
      if (row.offset) {
        // from where the last row aimed at the tube landed (resolved: rows resolve in order)
        size_t j = i;
        while (j > 0 && !script_.frames(tool)[j - 1].at_tube) --j;
        f[i].tip = f[j - 1].tip + row.tip;
      } else {
        f[i].tip = AimOnTube(tube, row);
      }
      pending[i] = false;
    }
  }
  return Interpolate(f, t);
}

}  // namespace viscera::script
