#include "mechanics/tip_coupling.h"

namespace viscera::mechanics {

using collision::ContactCandidate;
using collision::ContactKind;

TipCoupling::TipCoupling(const Model& model, const collision::SphereChain& chain,
                         const ContactLaw& law)
    : model_(model), chain_(chain), law_(law) {
  const size_t tools = model.params().tools.size();
  from_.assign(tools, Vec3::Zero());
  to_.assign(tools, Vec3::Zero());
  coupling_rows_.assign(tools, TipRows{});
  rows_.assign(tools, TipRows{});
  coupling_saturated_.assign(tools, 0);
  links_.reserve(tools * (chain.size() + 1));
  pairs_.reserve(tools * chain.size());
  released_.reserve(tools * chain.size());
  stiffened_.reserve(tools * chain.size());
  activated_.reserve(tools * chain.size());
}

void TipCoupling::Place(const State& state, double fraction) {
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
    const Vec3 target = from_[t] + fraction * (to_[t] - from_[t]);
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
  rows_ = coupling_rows_;  // the force evaluations start from these; same size: no allocation
}

void TipCoupling::AddContactCoupling(int candidate, int tool, int sphere, const ContactPenalty& p,
                                     const ContactLaw::Law& law, const Mat3& kn, const Mat3& dn) {
  // The pair's relative velocity is the sphere's minus L times the tip's (L the lever rule's
  // map, symmetric): J^T H J with J = [J_a, -L] gives the tip L H L and each window point's
  // block with the tip -w_i H L.
  const Mat3 lever = p.lever.Matrix();
  rows_[tool].k += lever * kn * lever;
  rows_[tool].d += lever * dn * lever;
  links_.push_back({Window(sphere), tool, -kn * lever, -dn * lever});
  pairs_.push_back({candidate, tool, sphere, p.lever, p.depth, law.force, law.slope, p.normal});
}

bool TipCoupling::Revise(double h, const Points& v, const double* dv, const VecX& tip_v,
                         const std::vector<ContactCandidate>& list,
                         const std::vector<PairGeometry>& geometry) {
  const double damping = model_.params().contacts.damping;
  auto end_velocity = [&](int sphere) { return Window(sphere).Gather(v, dv); };
  bool revised = false;
  // Pairs that did not act and end in contact act in the next solve.
  for (size_t i = 0; i < list.size(); ++i) {
    const ContactCandidate& c = list[i];
    const PairGeometry& g = geometry[i];
    if (c.kind != ContactKind::kTool || g.lever.fraction <= 0.0 ||
        g.clearance > 2.0 * model_.params().radius)
      continue;
    const int index = static_cast<int>(i);
    bool acted = Activated(index);
    for (const Pair& pair : pairs_) acted = acted || pair.candidate == index;
    for (int released : released_) acted = acted || released == index;
    if (acted) continue;
    const double vn = g.normal.dot(end_velocity(c.a) - g.lever.Apply(tip_v.segment<3>(3 * c.b)));
    if (g.depth - h * vn <= 0.0) continue;
    activated_.push_back(index);
    revised = true;
  }
  for (const Pair& pair : pairs_) {
    const Vec3 sphere = end_velocity(pair.sphere);
    const double vn = pair.normal.dot(sphere - pair.lever.Apply(tip_v.segment<3>(3 * pair.tool)));
    // What the linearized law applied at the end: its force at the start, h vn shallower, and
    // its damping at the end's speed.
    const double end_depth = pair.depth - h * vn;
    const double linear = pair.force + pair.slope * (end_depth - pair.depth);
    if (linear - damping * vn < 0.0) {
      released_.push_back(pair.candidate);
      revised = true;
      continue;
    }
    const ContactLaw::Law end = law_.At(end_depth);
    if (end_depth > 0.0 && end.force > 1.05 * linear && end.slope > pair.slope) {
      stiffened_.push_back({pair.candidate, end.slope});
      revised = true;
    }
  }
  return revised;
}

Vec3 TipCoupling::OnHand(int index, double h, const Vec3& start_velocity,
                         const ToolState& ts) const {
  const ToolParams& tp = model_.params().tools[index];
  // The force the solve's coupling put on the tip, linearized at the sub-step's start and
  // evaluated at its end (what implicit Euler applied); the hand feels its reaction.
  const TipRows& rows = coupling_rows_[index];
  Vec3 on_tip = rows.force - rows.d * (ts.tip_velocity - start_velocity);
  if (!coupling_saturated_[index]) on_tip -= rows.k * (h * ts.tip_velocity);
  // The damper the hand feels fades with the coupling (idle); the tip's own does not.
  return -on_tip - (1.0 - ts.coupling_scale) * tp.coupling_damping * ts.tip_velocity;
}

}  // namespace viscera::mechanics
