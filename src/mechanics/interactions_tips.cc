// The tools with their tips in the implicit solve (docs/tool-coupling.md; TipCoupling holds
// the tips' rows): the tools' capsules follow the state's tips, and each sub-step sets the
// targets' path, the coupling and the grasps; the solve moves the tips.
#include "mechanics/interactions.h"

namespace viscera::mechanics {

void Interactions::SyncTools(const State& state) {
  bool moved = false;
  for (size_t t = 0; t < state.tools.size() && t < geometry_.capsules().size(); ++t) {
    const ToolState& ts = state.tools[t];
    tool_velocity_[t] = ts.initialized ? ts.tip_velocity : Vec3::Zero();
    if (!ts.initialized) {
      moved = moved || geometry_.capsule(t).present;  // a state from before the first target
      geometry_.HideTool(t);
      continue;
    }
    const collision::ToolCapsule& capsule = geometry_.capsule(t);
    moved = moved || !capsule.present || capsule.tip != ts.tip;
    geometry_.PlaceTool(t, ts.tip);
  }
  if (moved) geometry_.RefreshTools();
}

void Interactions::PrepareTool(int index, double h, const Points& q, ToolState* ts) {
  const ToolTarget& target = ts->target;
  bool active = false;
  if (!FollowTarget(index, h, ts, &active)) return;
  // The target moves across the step from where it was to where it is, as the device's hand did.
  const double f0 = static_cast<double>(substep_) / substeps_,
               f1 = static_cast<double>(substep_ + 1) / substeps_;
  tips_.SetPath(index, ts->target_from + f0 * (target.tip - ts->target_from),
                ts->target_from + f1 * (target.tip - ts->target_from));
  tool_velocity_[index] = ts->tip_velocity;
  geometry_.PlaceTool(index, ts->tip);
  grasps_.Update(index, h, active, q, ts);
}

void Interactions::PlaceTips(const State& state, double fraction) {
  SyncTools(state);
  tips_.Place(state, fraction);
}

bool Interactions::ReviseTipContacts(double h, const Points& v, const double* dv,
                                     const VecX& tip_v) {
  return tips_.Revise(h, v, dv, tip_v, candidates(), geometry_.penalties());
}

void Interactions::TipAdvanced(int index, double h, ToolState* ts) {
  haptic_.AddImpulse(index, h, tips_.OnHand(index, h, tool_velocity_[index], *ts),
                     tips_.saturated(index));
  ts->tissue_force = tips_.rows()[index].tissue;
}

}  // namespace viscera::mechanics
