#include "script/script_player.h"

#include <utility>

namespace viscera::script {

ScriptPlayer::ScriptPlayer(ToolScript script) : script_(std::move(script)) {
  for (const std::string& tool : script_.tools()) {
    Rows& r = rows_[tool];
    r.written = script_.frames(tool);
    r.played = r.written;
    for (const ToolKeyframe& k : r.written) r.pending.push_back(k.at_tube || k.offset);
  }
}

void ScriptPlayer::Rows::Resolve(double t, const Tube& tube, size_t last) {
  if (tube.centre_line.empty()) return;
  for (size_t i = 0; i <= last && i < written.size(); ++i) {
    if (i > 0 && t < written[i - 1].t) break;  // its segment has not begun
    if (!pending[i]) continue;
    const ToolKeyframe& row = written[i];
    if (row.offset) {
      // from where the last row aimed at the tube landed (resolved: rows resolve in order); a
      // reach played again that holds no such row keeps the offset's first landing
      size_t j = i;
      while (j > 0 && !written[j - 1].at_tube) --j;
      if (j > 0) played[i].tip = played[j - 1].tip + row.tip;
    } else {
      played[i].tip = AimOnTube(tube, row);
    }
    pending[i] = false;
  }
}

bool ScriptPlayer::AtAimedPart(const ToolKeyframe& row, const Tube& tube, const Vec3* tip) {
  if (tip == nullptr || tube.centre_line.size() < 2) return true;  // nothing to look at
  return AlongTubeFrom(tube, row.along, *tip) <= 2.0 * tube.radius;
}

ScriptPlayer::Reach ScriptPlayer::BeginReach(const std::string& tool, size_t row, double t,
                                             const Vec3& from) const {
  const Rows& r = rows_.at(tool);
  size_t a = row;  // the tool's last row before the grasp not aimed at the tube: it backs off there
  while (a > 0 && (r.written[a].at_tube || r.written[a].offset)) --a;
  // it takes as long to back off as the script gave it to leave that point (no time when the
  // grasp row is the tool's first: it reaches again where it is)
  const double back = a < row ? r.written[a + 1].t - r.written[a].t : 0.0;
  Reach reach;
  reach.tool = tool;
  reach.row = row;
  ToolKeyframe now = r.written[row];
  now.t = t;
  now.tip = from;
  now.at_tube = now.offset = now.grasp = false;
  reach.rows.written.push_back(now);
  reach.rows.played.push_back(now);
  reach.rows.pending.push_back(false);
  for (size_t i = a; i <= row; ++i) {
    ToolKeyframe k = r.written[i];
    k.t = t + back + (r.written[i].t - r.written[a].t);
    reach.rows.written.push_back(k);
    ToolKeyframe p = r.played[i];
    p.t = k.t;
    reach.rows.played.push_back(p);
    reach.rows.pending.push_back(k.at_tube || k.offset);
  }
  return reach;
}

ToolKeyframe ScriptPlayer::At(const std::string& tool, double t, const Tube& tube,
                              const Vec3* tip) {
  Rows& r = rows_.at(tool);
  if (reach_ && reach_->tool != tool) {
    // the script's clock stands at the grasp row while another tool reaches again
    const double frozen = rows_.at(reach_->tool).written[reach_->row].t;
    r.Resolve(frozen, tube, r.written.size() - 1);
    return Interpolate(r.played, frozen);
  }
  if (reach_) {
    Rows& again = reach_->rows;
    again.Resolve(t, tube, again.written.size() - 1);
    if (t < again.played.back().t) return Interpolate(again.played, t);
    if (reach_->tries < kMaxReaches && !AtAimedPart(again.played.back(), tube, tip)) {
      const int tries = reach_->tries;
      reach_ = BeginReach(tool, reach_->row, t, again.played.back().tip);
      reach_->tries = tries + 1;
      ++reaches_;
      return Interpolate(reach_->rows.played, t);
    }
    // arrived: the script goes on from the grasp row, aimed where the last reach landed
    r.played[reach_->row].tip = again.played.back().tip;
    delay_ = t - r.written[reach_->row].t;
    r.next_grasp = reach_->row + 1;
    reach_.reset();
  }
  const double s = t - delay_;  // the script's time
  size_t& g = r.next_grasp;
  while (g < r.written.size() && !r.written[g].grasp) ++g;
  if (g < r.written.size() && s >= r.written[g].t) {
    r.Resolve(r.written[g].t, tube, g);  // up to the grasp row, as they came
    if (!AtAimedPart(r.played[g], tube, tip)) {
      reach_ = BeginReach(tool, g, t, r.played[g].tip);
      reach_->tries = 1;
      ++reaches_;
      return Interpolate(reach_->rows.played, t);
    }
    ++g;
  }
  r.Resolve(s, tube, r.written.size() - 1);
  return Interpolate(r.played, s);
}

}  // namespace viscera::script
