#include "mechanics/interactions.h"

#include "mechanics/avx_clone.h"

#include <algorithm>
#include <cmath>

namespace viscera::mechanics {
namespace {

using collision::ContactCandidate;
using collision::ContactKind;

// Verlet skin, in radii: a settled pile moved by a tool is searched every few tens of 1 kHz steps,
// and the narrow phase sees about a third more candidates than it must (docs/contacts.md).
constexpr double kVerletSkin = 0.5;

double Margin(const Model& model) {
  const double m = model.params().contacts.margin;
  return m >= 0.0 ? m : 0.25 * model.params().radius;
}

// Spheres whose rest distance along the chain is below one diameter overlap at rest: skip them.
int SelfSkip(const collision::SphereChain& chain) {
  return static_cast<int>(std::floor(2.0 * chain.radius() / chain.spacing())) + 1;
}

bool TipsInSolve(const Model& model) {
  return model.params().integrator == IntegratorKind::kImplicitEuler &&
         model.params().contacts.tips_in_solve;
}

}  // namespace

bool Interactions::Needed(const Model& model) {
  const ModelParams& p = model.params();
  return p.contacts.self || !p.obstacles.empty() || !p.tools.empty();
}

Interactions::Interactions(const Model& model)
    : model_(model),
      law_(model.params().contacts, model.params().radius),
      radius_(model.params().radius),
      margin_(Margin(model)),
      kinematics_(model),
      candidates_(collision::ContactDetector(radius_, margin_, model.params().contacts.self,
                                             SelfSkip(chain())),
                  kVerletSkin * radius_),
      grasps_(model, chain(), SelfSkip(chain())),
      geometry_(model, chain(), candidates_, grasps_),
      self_pairs_(static_cast<size_t>(chain().size()) * 8),
      impacts_(model, chain(), candidates_, &geometry_, SphereMass()),
      friction_(model.params().contacts, chain(), SphereMass()),
      tips_(model, chain(), law_),
      haptic_(model, TipsInSolve(model)) {
  const size_t tools = model.params().tools.size();
  tool_velocity_.assign(tools, Vec3::Zero());
  tips_in_solve_ = TipsInSolve(model);
  sphere_k_.assign(chain().size(), Mat3::Zero());
  sphere_d_.assign(chain().size(), Mat3::Zero());
  sphere_touched_.assign(chain().size(), 0);
  tip_contacts_.reserve(chain().size());
  Configure(model.params().initial_q, true);
}

void Interactions::Configure(const Points& q, bool place) {
  if (!kinematics_.Configure(q, place)) return;
  geometry_.Invalidate();
  impacts_.ChainMoved();
}

void Interactions::UpdateCandidates(double margin, State* state) {
  if (candidates_.Update(chain().spheres(), model_.params().obstacles, geometry_.capsules(),
                         margin)) {
    geometry_.Invalidate();
    // The state's list keeps the workspace's capacity: it grows only when the search's did.
    const collision::VerletMemory& memory = candidates_.memory();
    state->broad_phase.candidates.reserve(memory.candidates.capacity());
    state->broad_phase = memory;
  }
}

void Interactions::FollowState(const State& state) {
  if (candidates_.Restore(state.broad_phase)) geometry_.Invalidate();
  if (grasps_.Follow(state)) geometry_.Invalidate();  // Held() changes
}

Vec3 Interactions::OtherVelocity(const ContactCandidate& c, const ShaftLever& lever) const {
  switch (c.kind) {
    case ContactKind::kSelf: return kinematics_.velocity(c.b);
    case ContactKind::kTool: return lever.Apply(tool_velocity_[c.b]);
    case ContactKind::kEnvironment: break;
  }
  return Vec3::Zero();
}

VISCERA_AVX_CLONE ContactPenalty Interactions::Evaluate(const ContactCandidate& c,
                                                        const PairGeometry& geometry) const {
  // Cheap rejection: too far apart to touch within the sub-step at any plausible speed.
  if (geometry.depth <= 0.0 && speculative_h_ == 0.0) {
    ContactPenalty p;
    static_cast<PairGeometry&>(p) = geometry;
    return p;
  }
  // Friction: the regularized law here, or the stick-slip law that AddForces adds
  // (StickSlipFriction).
  return law_.Evaluate(c.kind, geometry,
                       kinematics_.velocity(c.a) - OtherVelocity(c, geometry.lever), speculative_h_,
                       friction_.active());
}

VISCERA_AVX_CLONE double Interactions::AddForces(const Points& q, const Points& qd, Points* F,
                                                 BlockBand* K, BlockBand* D) {
  const ContactParams& cp = model_.params().contacts;
  Configure(q, false);
  kinematics_.Gather(qd);
  geometry_.Ensure();
  double energy = friction_.energy();
  self_pairs_.Clear();
  friction_.ClearPairs();
  tips_.StartForces();  // the coupling's part (PlaceTips)
  // A pair apart by more than anything can close in the sub-step is one Evaluate leaves
  // inactive (most of the Verlet list's skin): skipped on its clearance alone. The margin
  // covers the rounding of Evaluate's closing speed.
  double tool_speed = 0.0;
  for (const Vec3& v : tool_velocity_) tool_speed = std::max(tool_speed, v.norm());
  const double reach = speculative_h_ * (2.0 * kinematics_.fastest() + tool_speed) * (1.0 + 1e-6);
  const auto& list = candidates();
  for (size_t i = 0; i < list.size(); ++i) {
    const ContactCandidate& c = list[i];
    const bool activated = c.kind == ContactKind::kTool && tips_.Activated(static_cast<int>(i));
    if (geometry_[i].clearance > reach && !activated) continue;
    if (c.kind == ContactKind::kTool && tips_.Released(static_cast<int>(i))) continue;
    ContactPenalty p = Evaluate(c, geometry_[i]);
    if (activated && !p.active) {
      // Its law (linear while apart) from the start, as a speculative pair's.
      const double vn = (kinematics_.velocity(c.a) - OtherVelocity(c, p.lever)).dot(p.normal);
      p.force = (law_.At(p.depth).force - cp.damping * vn) * p.normal;
      p.active = true;
    }
    ContactLaw::Law law = law_.At(p.depth);
    if (p.depth > 0.0) energy += law.energy;
    if (c.kind == ContactKind::kTool) law.slope = tips_.Slope(static_cast<int>(i), law.slope);
    if (!p.active) continue;
    const bool stick_slip = friction_.active();
    Mat3 friction_k, friction_d;
    if (stick_slip) {
      friction_k.setZero();
      friction_d.setZero();
      friction_.Add(c, law_.Friction(c.kind), &p, &friction_k, &friction_d);
    }
    Window(c.a).Scatter(p.force, F);
    const bool self = c.kind == ContactKind::kSelf;
    if (self) Window(c.b).Scatter(-p.force, F);
    const bool tool = c.kind == ContactKind::kTool;
    if (tool) tips_.AddContactForce(c.b, p.lever, p.force);
    if (!K) continue;
    const Mat3 nn = p.normal * p.normal.transpose();
    const double fn = std::max(0.0, p.force.dot(p.normal));
    // The regularized law's friction is viscous at the slip speed's slope; stick-slip friction is
    // a spring and damper while stuck and a constant force while sliding
    // (docs/friction.md).
    Mat3 kn = law.slope * nn;
    Mat3 dn = cp.damping * nn;
    if (stick_slip) {
      kn += friction_k;
      dn += friction_d;
    } else {
      dn += (law_.Friction(c.kind) * fn / kFrictionSlip) * (Mat3::Identity() - nn);
    }
    if (tool && tips_in_solve_)
      tips_.AddContactCoupling(static_cast<int>(i), c.b, c.a, p, law, kn, dn);
    // A self pair couples two windows far apart in the chain, outside the band: each side gets
    // twice the pair's coupling on its own window (exact for the pair's relative motion, and an
    // upper bound of the exact matrix, so a good preconditioner); the integrator removes the
    // excess on the pair's common motion (AddCommonModeTerms) so that no drag is added.
    const double scale = self ? 2.0 : 1.0;
    for (int side = 0; side < (self ? 2 : 1); ++side) {
      const int sphere = side == 0 ? c.a : c.b;
      if (!sphere_touched_[sphere]) {
        sphere_touched_[sphere] = 1;
        sphere_k_[sphere].setZero();
        sphere_d_[sphere].setZero();
      }
      sphere_k_[sphere] += scale * kn;
      sphere_d_[sphere] += scale * dn;
    }
    if (self && cp.exact_pairs) self_pairs_.Add(Window(c.a), Window(c.b), kn, dn);
  }
  if (K) {
    for (int k = 0; k < chain().size(); ++k) {
      if (!sphere_touched_[k]) continue;
      sphere_touched_[k] = 0;
      Window(k).AddOuter(sphere_k_[k], D ? &sphere_d_[k] : nullptr, K, D);
    }
  }
  // Grasps: a stiff spring from the jaws to the grasped curve point.
  for (int t = 0; t < grasps_.size(); ++t) {
    if (!grasps_.grasping(t)) continue;
    const double k = grasps_.Stiffness(t);
    const Vec3 x = grasps_.Stretch(t, geometry_.capsule(t).tip, q);
    energy += 0.5 * k * x.squaredNorm();
    const ContactWindow at = ContactWindow::Of(grasps_.at(t));
    at.Scatter(k * x, F);
    tips_.AddGraspForce(t, k * x);
    if (K) {
      at.AddOuter(k * Mat3::Identity(), nullptr, K, nullptr);
      if (tips_in_solve_) tips_.AddGraspCoupling(t, at, k);
    }
  }
  return energy;
}

double Interactions::CandidateMargin(const State& state, double h) const {
  // Twice the fastest travel in h: two spheres may close in on each other.
  double tool_speed = 0.0;
  for (const ToolState& t : state.tools) tool_speed = std::max(tool_speed, t.tip_velocity.norm());
  return margin_ + 2.0 * h * (kinematics_.fastest() + tool_speed);
}

VISCERA_AVX_CLONE int Interactions::RequiredSubsteps(State* state_in) {
  const State& state = *state_in;
  const int base = model_.params().substeps;
  const double h = model_.step_size();
  FollowState(state);        // usually as EndStep left it: nothing to take
  Configure(state.q, true);  // nor to redo
  // The step's impulse on each hand starts from nothing (a blown-up step's NaN stays in it).
  haptic_.StartStep();
  kinematics_.Gather(state.qd);
  SyncTools(state);
  const double margin = CandidateMargin(state, h);
  UpdateCandidates(margin, state_in);
  geometry_.Ensure();
  impacts_.Limit(h, &state_in->qd, nullptr, kinematics_.FastestAt(state.qd));
  kinematics_.Gather(state.qd);
  substep_ = 0;
  double closing = 0.0;
  const auto& list = candidates();
  for (size_t i = 0; i < list.size(); ++i) {
    const ContactCandidate& c = list[i];
    const PairGeometry& p = geometry_[i];
    if (p.clearance >= margin) continue;  // the list's skin: too far to meet within the step
    // A tip in the solve meets the tube within it (its contacts act speculatively on both): the
    // step's rate, not the tool's approach, sets its sub-steps, so that the hand feels the same
    // coupling near the tube as in free space.
    if (tips_in_solve_ && c.kind == ContactKind::kTool) continue;
    const Vec3 relative = kinematics_.velocity(c.a) - OtherVelocity(c, p.lever);
    closing = std::max(closing, -relative.dot(p.normal));
  }
  const int needed = static_cast<int>(std::ceil(closing * h / (0.2 * radius_)));
  candidates_fresh_ = true;
  substeps_ = std::clamp(needed, base, std::max(base, kMaxSubsteps));
  return substeps_;
}

void Interactions::BeginSubstep(std::span<const ToolTarget> targets, double h, State* state) {
  if (!targets.empty()) {
    for (size_t t = 0; t < state->tools.size() && t < targets.size(); ++t) {
      ToolState& ts = state->tools[t];
      // The new target is where the hand is at the end of the step; it was at the old one.
      ts.target_from = ts.initialized && ts.target.tip.allFinite() ? ts.target.tip : targets[t].tip;
      ts.target = targets[t];
    }
  }
  speculative_h_ = model_.params().integrator == IntegratorKind::kImplicitEuler ? h : 0.0;
  // Candidates must include every pair that can meet within the sub-step (those found for the
  // whole step do, for its first sub-step, whose velocities RequiredSubsteps gathered).
  if (!candidates_fresh_) {
    Configure(state->q, true);
    kinematics_.Gather(state->qd);
  }
  const double margin = CandidateMargin(*state, h);
  if (!candidates_fresh_) UpdateCandidates(margin, state);
  candidates_fresh_ = false;
  if (!state->tools.empty()) {
    // Tools move against the candidates of their current pose; then find those of the new one.
    for (size_t t = 0; t < state->tools.size(); ++t) {
      if (tips_in_solve_) {
        PrepareTool(static_cast<int>(t), h, state->q, &state->tools[t]);
      } else {
        AdvanceTool(static_cast<int>(t), h, state->q, state->qd, &state->tools[t]);
      }
    }
    substep_ = std::min(substep_ + 1, substeps_ - 1);
    UpdateCandidates(margin, state);
    geometry_.RefreshTools();
  }
  if (impacts_.Limit(h, &state->qd, nullptr, kinematics_.FastestAt(state->qd)))
    state->last_h = 0.0;  // q̇ took impulses: the implicit step's BDF2 restarts
}

void Interactions::ReleaseHeldSpheres(State* state) {
  for (int t = 0; t < grasps_.size(); ++t) {
    if (grasps_.held_sphere(t) < 0 || grasps_.grasping(t)) continue;
    bool inside = false;
    for (const ContactCandidate& c : candidates()) {
      if (grasps_.Held(c) && c.b == t && geometry_.Raw(c).clearance < 0.0) inside = true;
    }
    if (!inside) {
      grasps_.Release(t);
      state->tools[t].held_sphere = -1;
      geometry_.Invalidate();  // its spheres are contacts again
    }
  }
}

void Interactions::EndStep(State* state) {
  // Re-placed here rather than at the next step's start: the geometry found for the statistics
  // is then the next step's too.
  FollowState(*state);  // as the sub-steps left it, unless the step reset the state
  Configure(state->q, true);
  if (tips_in_solve_) SyncTools(*state);
  ReleaseHeldSpheres(state);
  geometry_.Ensure();
  ContactStats stats;
  const auto& list = candidates();
  for (size_t i = 0; i < list.size(); ++i) {
    const ContactCandidate& c = list[i];
    const PairGeometry& p = geometry_[i];
    if (std::isnan(stats.min_clearance) || p.clearance < stats.min_clearance) {
      stats.min_clearance = p.clearance;
      stats.deepest = c.kind == ContactKind::kSelf   ? "self"
                      : c.kind == ContactKind::kTool ? "tool"
                                                     : "environment";
    }
    if (p.clearance >= margin_) continue;
    switch (c.kind) {
      case ContactKind::kSelf: ++stats.self; break;
      case ContactKind::kEnvironment: ++stats.environment; break;
      case ContactKind::kTool: ++stats.tool; break;
    }
  }
  state->contacts = stats;

  haptic_.EndStep(list, geometry_.penalties(), law_, grasps_, state);
}

}  // namespace viscera::mechanics
