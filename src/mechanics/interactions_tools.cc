// The laparoscopic tools' part of Interactions: the tip's virtual coupling, integrated in short
// cycles against the tissue's one-sided reactions, and the grasp.
#include "mechanics/interactions.h"

#include <algorithm>
#include <cmath>

namespace viscera::mechanics {
namespace {

using collision::ContactCandidate;
using collision::ContactKind;

constexpr double kCouplingTimeConstant = 0.05;  // s: coupling fades in / out (idle device)
// s: the tip's own integration step. The tip is 3 degrees of freedom against a stiff coupling
// (300 N/m on 50 g): integrated once per 5 or 10 ms sub-step, implicit Euler's lag made the
// force on the hand depend on the rate; 0.1 ms cycles cost a few microseconds and make it exact
// to well under 1 % at every rate.
constexpr double kTipCycle = 1e-4;

}  // namespace

bool Interactions::FollowTarget(int index, double h, ToolState* ts, bool* active_out) {
  const ToolTarget& target = ts->target;
  const bool active = target.active && target.tip.allFinite() && std::isfinite(target.jaw);
  if (!ts->initialized) {
    grasps_.Clear(index);
    geometry_.HideTool(index);
    if (!active) return false;
    ts->tip = target.tip;  // the tip starts at the first target
    ts->tip_velocity.setZero();
    ts->initialized = true;
  }
  // Coupling fades in and out rather than jumping (a device that stops sending goes limp).
  const double goal = active ? 1.0 : 0.0;
  ts->coupling_scale += (goal - ts->coupling_scale) * (1.0 - std::exp(-h / kCouplingTimeConstant));
  ts->jaw = active ? std::clamp(target.jaw, 0.0, 1.0) : 1.0;
  if (active) ts->orientation = target.orientation.normalized();
  *active_out = active;
  return true;
}

void Interactions::AdvanceTool(int index, double h, const Points& q, const Points& qd,
                               ToolState* ts) {
  const ToolParams& tp = model_.params().tools[index];
  const ContactParams& cp = model_.params().contacts;
  const ToolTarget& target = ts->target;
  bool active = false;
  if (!FollowTarget(index, h, ts, &active)) return;

  // Reactions of the tissue on the tool at the current pose, moved to the tip by the lever rule
  // (the shaft pivots at the port): each contact's force at the start and its stiffness.
  Configure(q, false);
  kinematics_.Gather(qd);
  geometry_.Ensure();
  tip_contacts_.clear();
  ts->tissue_force.setZero();
  const auto& list = candidates();
  for (size_t i = 0; i < list.size(); ++i) {
    const ContactCandidate& c = list[i];
    if (c.kind != ContactKind::kTool || c.b != index) continue;
    const ContactPenalty p = Evaluate(c, geometry_[i]);
    if (!p.active) continue;
    tip_contacts_.push_back(
        {p.normal, p.lever, p.depth, kinematics_.velocity(c.a) - OtherVelocity(c, p.lever)});
    ts->tissue_force += p.force;  // on the tube where it touches, before the lever rule
  }
  Vec3 grasp_force = Vec3::Zero();
  Vec3 grasp_travel = Vec3::Zero();
  double grasp_k = 0.0;
  if (grasps_.grasping(index)) {
    grasp_k = grasps_.Stiffness(index);
    // The tube's grasped point moves after the tip, by v h over the sub-step; the cycles move it
    // there linearly, as they move the target. Held where it was, the spring lagged the tube by
    // v h and the hand felt k v h more while lifting at larger steps; held where it will be at
    // the sub-step's end, the tip (an 8 ms time constant on its coupling and grasp) was pulled
    // ahead from the start and the hand felt up to k v h / 2 less (12 % at 100 Hz lifting the
    // cavity's mid-gut at 6.5 cm/s).
    grasp_travel = h * Model::Evaluate(grasps_.at(index), qd);
    grasp_force = -grasp_k * grasps_.Stretch(index, geometry_.capsule(index).tip, q);
    ts->tissue_force -= grasp_force - grasp_k * grasp_travel;  // at the sub-step's end, on the tube
  }
  // Virtual coupling to the target, which moves from where it was at the start of the sub-step
  // to where it is at its end; the tool's own weight is not simulated (not felt). The tip runs
  // through short cycles of linearly implicit Euler, (m + dt c + dt^2 K) dv = dt (F - dt K v),
  // against the tissue's reactions linearized about the start, each one-sided: a contact acts
  // while it pushes. (A pair closing fast acts before it touches, so that an impact is not found
  // late and deep; held linear, it pulled a tip that stopped short toward the tube, 0.05 N.) The
  // coupling pulls the tip with the force the hand feels, so it is limited like it by the
  // device's maximum: a target that jumps 8 cm no longer throws the tip through the tube at 3 m/s.
  const double kc = ts->coupling_scale * tp.coupling_stiffness;
  const bool coupled = target.tip.allFinite() && ts->target_from.allFinite();
  const double f0 = static_cast<double>(substep_) / substeps_,
               f1 = static_cast<double>(substep_ + 1) / substeps_;
  const Vec3 from = ts->target_from + f0 * (target.tip - ts->target_from);
  const Vec3 to = ts->target_from + f1 * (target.tip - ts->target_from);
  const int cycles = std::max(1, static_cast<int>(std::ceil(h / kTipCycle - 1e-9)));
  const double dt = h / cycles;
  const Vec3 tip0 = ts->tip, tip_velocity0 = ts->tip_velocity;
  for (int i = 1; i <= cycles; ++i) {
    const Vec3 moved = ts->tip - tip0;
    const double u = static_cast<double>(i) / cycles;
    Vec3 tissue = grasp_force - grasp_k * (moved - u * grasp_travel);
    Mat3 stiffness = grasp_k * Mat3::Identity();
    Mat3 contact_damping = Mat3::Zero();
    for (const TipContact& tc : tip_contacts_) {
      // The whole contact law at this cycle's depth and speed (Evaluate's, with the tube held
      // where it was at the sub-step's start), not the start's linearization: beyond 5 % of R
      // the law stiffens 100-fold within a millimetre; friction's slope (30 f_n N s/m) held
      // from the start made the 50 g tip ring along the tube at 1 cm/s on the stiffer contact,
      // and extrapolated linearly it exceeded the Coulomb limit by up to 8 N within a sub-step.
      // The tip moving along L n (n from the shaft to the sphere, L the lever rule's map)
      // presses the contact deeper.
      const Mat3 lever = tc.lever.Matrix();
      const Vec3 axis = lever * tc.normal;
      const double depth = tc.depth + axis.dot(moved);
      const Vec3 relative = tc.relative - lever * (ts->tip_velocity - tip_velocity0);
      const double vn = relative.dot(tc.normal);
      const ContactLaw::Law law = law_.At(depth);
      const double fn = law.force - cp.damping * vn;
      if (!(fn > 0.0) || tc.lever.fraction <= 0.0)
        continue;  // it would pull: the tube does not hold the tool
      const Vec3 vt = relative - vn * tc.normal;
      const double mu = law_.Friction(ContactKind::kTool);
      const double slip_slope = mu * fn / kFrictionSlip;  // the viscous slope, as AddForces
      const Vec3 on_sphere = fn * tc.normal - (mu * fn / std::max(vt.norm(), kFrictionSlip)) * vt;
      tissue -= lever * on_sphere;  // on the tool, moved to the tip by the lever rule
      const Mat3 nn = tc.normal * tc.normal.transpose();
      stiffness += law.slope * (axis * axis.transpose());
      contact_damping += lever * (cp.damping * nn + slip_slope * (Mat3::Identity() - nn)) * lever;
    }
    Vec3 spring = Vec3::Zero();
    if (coupled) spring = kc * (from + (static_cast<double>(i) / cycles) * (to - from) - ts->tip);
    const Vec3 damping = -tp.coupling_damping * ts->tip_velocity;
    // Saturated, the spring's pull is a constant force this cycle (0.1 ms: explicit is fine) and
    // adds no stiffness; its damping still acts. (Saturating both left an undamped tip bouncing
    // 12-31 cm at up to 2.3 m/s around where the device's 5 N balanced the tissue.)
    const double size = spring.norm();
    const bool saturated = size > tp.max_force;
    if (saturated) spring *= tp.max_force / size;
    const Mat3 k_total = saturated ? stiffness : Mat3(stiffness + kc * Mat3::Identity());
    const Mat3 a = (tp.mass + dt * tp.coupling_damping) * Mat3::Identity() + dt * contact_damping +
                   dt * dt * k_total;
    ts->tip_velocity +=
        a.inverse() * (dt * (tissue + spring + damping - dt * k_total * ts->tip_velocity));
    ts->tip += dt * ts->tip_velocity;
  }
  tool_velocity_[index] = ts->tip_velocity;
  geometry_.PlaceTool(index, ts->tip);

  grasps_.Update(index, h, active, q, ts);
}

}  // namespace viscera::mechanics
