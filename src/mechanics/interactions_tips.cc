// The tools' tips as unknowns of the implicit solve (docs/tool-coupling.md): the
// virtual coupling to the device's target and the tip's mass give each tip its own rows;
// AddForces adds every tip-tube contact and grasp to them and to the links between a tip and the
// tube's windows, which the integrator eliminates by a Schur complement.
#include <algorithm>
#include <cmath>

#include "mechanics/interactions.h"

namespace viscera::mechanics {
namespace {

using collision::ContactCandidate;
using collision::ContactKind;

}  // namespace

void Interactions::SyncTools(const State& state) {
  bool moved = false;
  for (size_t t = 0; t < state.tools.size() && t < capsules_.size(); ++t) {
    const ToolState& ts = state.tools[t];
    tool_velocity_[t] = ts.initialized ? ts.tip_velocity : Vec3::Zero();
    if (!ts.initialized) {
      moved = moved || capsules_[t].present;  // a state from before the tool's first target
      capsules_[t].present = false;
      continue;
    }
    const ToolParams& tp = model_.params().tools[t];
    moved = moved || !capsules_[t].present || capsules_[t].tip != ts.tip;
    capsules_[t] = {true, tp.port, ts.tip, tp.radius};
  }
  if (moved) RefreshToolGeometry();
}

void Interactions::PrepareTool(int index, double h, const Points& q, ToolState* ts) {
  const ToolParams& tp = model_.params().tools[index];
  const ToolTarget& target = ts->target;
  bool active = false;
  if (!FollowTarget(index, h, ts, &active)) return;
  // The target moves across the step from where it was to where it is, as the device's hand did.
  const double f0 = static_cast<double>(substep_) / substeps_,
               f1 = static_cast<double>(substep_ + 1) / substeps_;
  tip_from_[index] = ts->target_from + f0 * (target.tip - ts->target_from);
  tip_to_[index] = ts->target_from + f1 * (target.tip - ts->target_from);
  tool_velocity_[index] = ts->tip_velocity;
  capsules_[index] = {true, tp.port, ts->tip, tp.radius};
  grasps_.Update(index, h, active, q, ts);
}

void Interactions::PlaceTips(const State& state, double fraction) {
  SyncTools(state);
  for (size_t t = 0; t < coupling_rows_.size(); ++t) {
    TipRows& rows = coupling_rows_[t];
    const ToolState& ts = state.tools[t];
    rows = TipRows{};
    coupling_saturated_[t] = 0;
    if (!ts.initialized) continue;
    const ToolParams& tp = model_.params().tools[t];
    rows.present = true;
    rows.mass = tp.mass;
    // The coupling: a spring to the target where it is at the end of this (part of the) sub-step
    // and a damper; the tool's own weight is not simulated (not felt).
    const double kc = ts.coupling_scale * tp.coupling_stiffness;
    Vec3 spring = Vec3::Zero();
    const Vec3 target = tip_from_[t] + fraction * (tip_to_[t] - tip_from_[t]);
    if (ts.target.tip.allFinite() && ts.target_from.allFinite()) spring = kc * (target - ts.tip);
    // The coupling pulls the tip with the force the hand feels, so the device's maximum limits
    // it: saturated, the spring is a constant force over the sub-step (no stiffness), its damper
    // still acts. A target that jumps 8 cm would otherwise throw the 50 g tip at 3 m/s.
    const double size = spring.norm();
    if (size > tp.max_force) {
      spring *= tp.max_force / size;
      coupling_saturated_[t] = 1;
    } else {
      rows.k = kc * Mat3::Identity();
    }
    rows.force = spring - tp.coupling_damping * ts.tip_velocity;
    rows.d = tp.coupling_damping * Mat3::Identity();
  }
  tip_rows_ = coupling_rows_;  // AddForces starts from these; same size: no allocation
}

bool Interactions::ReviseTipContacts(double h, const Points& v, const double* dv,
                                     const VecX& tip_v) {
  const double damping = model_.params().contacts.damping;
  auto end_velocity = [&](int sphere) { return Window(sphere).Gather(v, dv); };
  bool revised = false;
  // Pairs that did not act and end in contact act in the next solve.
  const auto& list = candidates();
  for (size_t i = 0; i < list.size(); ++i) {
    const ContactCandidate& c = list[i];
    const ContactPenalty& g = geometry_[i];
    if (c.kind != ContactKind::kTool || g.lever <= 0.0 || g.clearance > 2.0 * radius_) continue;
    const int index = static_cast<int>(i);
    bool acted = TipActivated(index);
    for (const TipPair& pair : tip_pairs_) acted = acted || pair.candidate == index;
    for (int released : tip_released_) acted = acted || released == index;
    if (acted) continue;
    const double vn = g.normal.dot(end_velocity(c.a) - g.lever * tip_v.segment<3>(3 * c.b));
    if (g.depth - h * vn <= 0.0) continue;
    tip_activated_.push_back(index);
    revised = true;
  }
  for (const TipPair& pair : tip_pairs_) {
    const Vec3 sphere = end_velocity(pair.sphere);
    const double vn = pair.normal.dot(sphere - pair.lever * tip_v.segment<3>(3 * pair.tool));
    // What the linearized law applied at the end: its force at the start, h vn shallower, and
    // its damping at the end's speed.
    const double end_depth = pair.depth - h * vn;
    const double linear = pair.force + pair.slope * (end_depth - pair.depth);
    if (linear - damping * vn < 0.0) {
      tip_released_.push_back(pair.candidate);
      revised = true;
      continue;
    }
    const ContactLaw::Law end = law_.At(end_depth);
    if (end_depth > 0.0 && end.force > 1.05 * linear && end.slope > pair.slope) {
      tip_stiffened_.push_back({pair.candidate, end.slope});
      revised = true;
    }
  }
  return revised;
}

void Interactions::TipAdvanced(int index, double h, ToolState* ts) {
  const ToolParams& tp = model_.params().tools[index];
  // The force the solve's coupling put on the tip, linearized at the sub-step's start and
  // evaluated at its end (what implicit Euler applied); the hand feels its reaction.
  const TipRows& rows = coupling_rows_[index];
  Vec3 on_tip = rows.force - rows.d * (ts->tip_velocity - tool_velocity_[index]);
  if (!coupling_saturated_[index]) on_tip -= rows.k * (h * ts->tip_velocity);
  // The damper the hand feels fades with the coupling (idle); the tip's own does not.
  const Vec3 on_hand =
      -on_tip - (1.0 - ts->coupling_scale) * tp.coupling_damping * ts->tip_velocity;
  haptic_.AddImpulse(index, h, on_hand, coupling_saturated_[index]);
  ts->tissue_force = tip_rows_[index].tissue;
}

}  // namespace viscera::mechanics
