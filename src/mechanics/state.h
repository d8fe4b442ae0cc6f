#pragma once
/// The mutable state of one simulation: plain, copyable, snapshot-able (the MuJoCo mjData
/// habit, minus the scratch, which lives in Workspace). It is the whole state: everything a step
/// reads from the steps before (the grasps, the solver's warm start, the broad phase's list) is
/// here, so that a step from a copy is bit for bit the same whatever its Workspace did before
/// (a restore after a blow-up, a reset, a fresh workspace; docs/mechanics.md, "State is the
/// whole state").
#include <cstdint>
#include <limits>
#include <vector>

#include "collision/verlet_list.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

/// Contacts after the last step: pairs in contact (penetrating or within the margin) and the
/// smallest signed clearance over the pairs examined (NaN when there were none).
struct ContactStats {
  int self = 0;
  int environment = 0;
  int tool = 0;
  double min_clearance = std::numeric_limits<double>::quiet_NaN();
  /// What the deepest pair touches: "self", "environment" or "tool" ("" without pairs).
  const char* deepest = "";
};

/// A contact that friction holds (docs/friction.md): the stretch of its tangential
/// spring, from where the contact stuck (sticking) or as far as the cone lets it (sliding).
struct FrictionAnchor {
  uint64_t key = 0;             ///< the pair: StickSlipFriction::Key(kind, a, b)
  Vec3 stretch = Vec3::Zero();  ///< m, in the contact's tangent plane when last stepped
  bool sliding = false;         ///< it slid in the last sub-step (the next one starts so)
};

struct State {
  double t = 0.0;                ///< simulated time (s)
  Points q;                      ///< control points (m), #N by 3
  Points qd;                     ///< their velocities (m/s), #N by 3
  std::vector<ToolState> tools;  ///< one per model tool: pose, grasp, force feedback
  ContactStats contacts;
  int64_t steps = 0;  ///< steps taken
  int substeps = 0;   ///< sub-steps the last step took (more during impacts)
  /// Steps whose result was not finite; each one reset the state to the model's start.
  int64_t nonfinite_resets = 0;
  /// Sub-steps whose linear solve stayed short of its tolerance even with more iterations and
  /// halved sub-steps, and was accepted as it was (ImplicitEulerIntegrator::cg_unconverged).
  int64_t unconverged_solves = 0;
  /// The implicit integrator's last sub-step, which its BDF2 builds on: how far it moved q and
  /// changed q̇, and its length (0: none the next sub-step may build on).
  Points last_dq;
  Points last_dqd;
  double last_h = 0.0;
  /// The implicit integrator's stick-slip friction: one anchor per contact that friction held in
  /// the last sub-step, in the order of the contact candidates (empty with the regularized law).
  std::vector<FrictionAnchor> friction;
  /// The implicit integrator's conjugate-gradient warm start (3N each): the last coupled
  /// sub-step's correction (exact answer minus the band's) and the one before, which the next
  /// extrapolates; zero after an uncoupled sub-step.
  VecX cg_correction;
  VecX cg_previous_correction;
  /// The broad phase's contact candidates (a Verlet list) and where each body was searched: the
  /// next step keeps them while nothing moved far, and sums its contacts in their order.
  collision::VerletMemory broad_phase;
};

/// The model's starting pose at rest, t = 0.
inline State InitialState(const Model& model) {
  State s;
  s.q = model.params().initial_q;
  s.qd = Points::Zero(model.num_points(), 3);
  s.last_dq = Points::Zero(model.num_points(), 3);
  s.last_dqd = Points::Zero(model.num_points(), 3);
  s.cg_correction = VecX::Zero(3 * model.num_points());
  s.cg_previous_correction = VecX::Zero(3 * model.num_points());
  s.tools.resize(model.params().tools.size());
  for (size_t i = 0; i < s.tools.size(); ++i) {
    s.tools[i].tip = model.params().tools[i].port;
    s.tools[i].target.active = false;  // idle until a device or script gives a target
  }
  return s;
}

/// Drops what a state carries for the solver and the broad phase of the model it ran with (CG's
/// warm start, the Verlet list), so that its next step starts them afresh, as a new workspace
/// would: for a state that goes on under another model (a scene's settling tightens the
/// mesentery stage by stage).
inline void ForgetSolverMemory(State* s) {
  s->cg_correction.setZero();
  s->cg_previous_correction.setZero();
  s->broad_phase = collision::VerletMemory{};
}

}  // namespace viscera::mechanics
