#pragma once
/// Everything that touches the intestine from outside its own elasticity, for one simulation:
/// the sphere chain and its contacts (self, environment, tools: penalty springs with damping and
/// regularized Coulomb friction, France et al. 2005 section 3.5), the laparoscopic tools with
/// their virtual coupling and grasps, and the haptic output. With the implicit integrator,
/// friction may have a static phase (contacts.friction_law; docs/friction.md). Coordinates one
/// class per job (ChainKinematics, ContactGeometry, ContactLaw, StickSlipFriction,
/// SelfPairCoupling, ImpactSets, Grasps, TipCoupling, HapticOutput). Owned by the stepping thread's
/// Workspace; allocates nothing in steady state.
#include <algorithm>
#include <span>
#include <vector>

#include "collision/contact_detector.h"
#include "collision/sphere_chain.h"
#include "collision/verlet_list.h"
#include "common/check.h"
#include "mechanics/block_band.h"
#include "mechanics/chain_kinematics.h"
#include "mechanics/contact_geometry.h"
#include "mechanics/contact_law.h"
#include "mechanics/contact_window.h"
#include "mechanics/grasps.h"
#include "mechanics/haptic_output.h"
#include "mechanics/impact_limiter.h"
#include "mechanics/impact_sets.h"
#include "mechanics/model.h"
#include "mechanics/self_pair_coupling.h"
#include "mechanics/state.h"
#include "mechanics/stick_slip_friction.h"
#include "mechanics/tip_coupling.h"

namespace viscera::mechanics {

class Interactions {
 public:
  explicit Interactions(const Model& model);

  /// Whether a model needs this at all (self-contacts, obstacles or tools).
  static bool Needed(const Model& model);

  /// Sub-steps this step needs so that no pair closes in by more than a fifth of the radius per
  /// sub-step (an impact found a sub-step late would start its penalty spring compressed,
  /// creating energy): at least the model's, at most kMaxSubsteps. First limits the impacts over
  /// the whole step (ImpactSets::Limit), so that a landing needs few sub-steps.
  int RequiredSubsteps(State* state);
  static constexpr int kMaxSubsteps = 32;

  /// At the start of a sub-step: takes new targets (empty: keep the last), advances the tools
  /// toward them (implicitly, against their contact and grasp reactions at the current pose),
  /// opens or closes grasps, re-places the spheres and finds the contact candidates.
  void BeginSubstep(std::span<const ToolTarget> targets, double h, State* state);

  /// Adds contact and grasp forces at (q, qd) to F (#N by 3), with the tools where
  /// BeginSubstep left them; returns their energy (J), the stuck contacts' tangential springs'
  /// included as the last sub-step left them. K, D as in ForceJacobians, kept in the
  /// chain's band: a self pair's coupling H enters as 2 H on each side's own window, which
  /// exceeds the exact (J_a - J_b)^T H (J_a - J_b) by the pair's common-mode term
  /// (J_a + J_b)^T H (J_a + J_b) (see AddCommonModeTerms; docs/self-coupling.md).
  double AddForces(const Points& q, const Points& qd, Points* F, BlockBand* K, BlockBand* D);

  /// Weighs the self pairs of the last AddForces with K for AddCommonModeTerms: C_p = ck K_p +
  /// cd D_p, once rather than at each of CG's products.
  void WeighCommonModes(double ck, double cd) { self_pairs_.Weigh(ck, cd); }
  /// y += sum over those pairs of (J_a + J_b)^T C_p (J_a + J_b) x (x, y #N by 3): what the band
  /// overstates. The exact K is the band's K minus this with (ck, cd) = (1, 0); the exact
  /// implicit matrix is the band's M + h D + h^2 K minus this with (h^2, h).
  /// @pre y has x's size and is not x.
  void AddCommonModeTerms(const Points& x, Points* y) const {
    VISCERA_ASSERT(x.cols() == 3 && y->rows() == x.rows() && y->cols() == 3 && y != &x);
    AddCommonModeTerms(x.data(), y->data());
  }
  /// The same on 3N values each, ordered x0 y0 z0 x1 ... (CG's vectors, without reshaping).
  /// @pre x and y each hold the chain's 3N values, and do not overlap (y is added to pair by
  /// pair while later pairs still read x).
  void AddCommonModeTerms(const double* x, double* y) const {
    self_pairs_.AddCommonModeTerms(x, y);
  }
  /// Self pairs that the last AddForces with K linearized (0: the band is exact).
  int coupled_pairs() const { return self_pairs_.size(); }

  /// What the implicit solve's impulses hold at the end of a sub-step (ImpactSets).
  using EndConstraint = ImpactSets::EndConstraint;
  /// ImpactSets::GatherEnd on this step's candidates.
  bool GatherEndConstraints(EndConstraint kind, double h, const Points& v_check,
                            const Points& v_base, bool first,
                            std::vector<ImpactLimiter::Contact>* contacts) {
    return impacts_.GatherEnd(kind, h, v_check, v_base, first, contacts);
  }

  /// With the implicit integrator the tools' tips are unknowns of the tube's solve (three per
  /// tool): the coupling to the device's target, the tip's mass and every contact and grasp
  /// between tip and tube enter one linear system, so action is reaction
  /// (docs/tool-coupling.md). With RK4 the tip runs its own short cycles at each sub-step's start.
  bool tips_in_solve() const { return tips_in_solve_; }
  /// Before the forces: the tips where state->tools has them, the coupling's target at
  /// `fraction` (0..1) of the sub-step BeginSubstep began.
  void PlaceTips(const State& state, double fraction);
  /// Filled by AddForces (with K) after PlaceTips.
  const std::vector<TipRows>& tip_rows() const { return tips_.rows(); }
  const std::vector<TipLink>& tip_links() const { return tips_.links(); }
  /// Each tip contact acts while it pushes, and with the stiffness it has where it ends: after a
  /// solve whose end velocities are v + dv (#N by 3, dv's 3N values) for the tube and tip_v for
  /// the tips (3 per tool), releases the tool contacts whose linearized force at the sub-step's
  /// end would pull (a contact predicted to close that the tip stops short of), and stiffens those
  /// whose law at the predicted end depth pushes more than 5 % beyond their linearization (the law
  /// stiffens 100-fold within 0.6 mm); says whether any changed, so that the solve is done again.
  /// ClearTipReleases starts a sub-step with every contact as its start's law has it.
  bool ReviseTipContacts(double h, const Points& v, const double* dv, const VecX& tip_v);
  void ClearTipReleases() {
    friction_.ClearRevisions();
    tips_.ClearRevisions();
  }
  /// After the solve moved tool `index`'s tip by h: the coupling force the solve applied, as the
  /// hand feels it, enters the step's impulse (EndStep reports its mean, then clamps it).
  void TipAdvanced(int index, double h, ToolState* ts);

  /// Stick-slip friction (StickSlipFriction; docs/friction.md) in the next force evaluations of a
  /// sub-step of length h, from the anchors it starts from; nullptr: the regularized law (RK4, or
  /// the scene's friction_law). The anchors must outlive those evaluations.
  void UseFriction(const std::vector<FrictionAnchor>* anchors, double h) {
    friction_.Use(anchors, h);
  }
  /// Once a sub-step is accepted: StickSlipFriction::Advance. Replaces state->friction.
  void AdvanceFriction(const Points& dq, double h, State* state) {
    friction_.Advance(dq, h, state);
  }
  /// After a solve: StickSlipFriction::Revise with the tips' start velocities. Says whether any
  /// contact changed. ClearTipReleases also starts a sub-step with every contact as its start has
  /// it.
  bool ReviseFriction(const Points& v, const double* dv, const double* tip_dv) {
    return friction_.Revise(v, dv, tip_dv, tool_velocity_);
  }
  /// After ReviseFriction: StickSlipFriction::ApplyRevisions (the revised pairs as the changes
  /// of the last evaluation's terms, or false when a tool's pair changed).
  bool ApplyFrictionRevisions(std::vector<StickSlipFriction::Change>* changes) {
    return friction_.ApplyRevisions(changes);
  }

  /// After the step: contact counts and clearance, tool force feedback (clamped), stiffness.
  void EndStep(State* state);

  const collision::SphereChain& chain() const { return kinematics_.chain(); }
  /// Every pair that may touch within the sub-step, and some farther (a Verlet list).
  const std::vector<collision::ContactCandidate>& candidates() const {
    return candidates_.candidates();
  }
  /// Broad-phase searches so far (the list is reused between them).
  int64_t searches() const { return candidates_.searches(); }
  /// Partial searches so far: only the bodies that moved far (collision::VerletList).
  int64_t partial_searches() const { return candidates_.partial_searches(); }

 private:
  // After a release, the jaws let go of the spheres they held once those are out of the shaft.
  void ReleaseHeldSpheres(State* state);
  // Takes what the state carries from the last step (the grasps, the broad phase's list), so
  // that a step continues the state it is given, not this workspace's last one (a restored
  // state, another workspace's). Nothing changes for the state this workspace last stepped.
  void FollowState(const State& state);
  // Velocity of the candidate's other side at the contact (zero for obstacles), from the
  // velocities last gathered.
  Vec3 OtherVelocity(const collision::ContactCandidate& c, const ShaftLever& lever) const;
  // The force law on a candidate's geometry, at the velocities last gathered (a pair apart is
  // left as it is without them where nothing acts speculatively).
  ContactPenalty Evaluate(const collision::ContactCandidate& c, const PairGeometry& geometry) const;
  ContactWindow Window(int sphere) const { return kinematics_.Window(sphere); }
  // ChainKinematics::Configure, and the geometry and impact sets invalidated if the chain moved.
  void Configure(const Points& q, bool place);
  // Finds the candidates for `margin`, keeping the geometry unless the list changed; a new list
  // goes to state->broad_phase.
  void UpdateCandidates(double margin, State* state);
  // One collision sphere's share of the tube's mass (kg): what an impact or a friction
  // overload moves.
  double SphereMass() const {
    return model_.params().mass * chain().spacing() / model_.params().length;
  }
  // Contact margin plus twice the fastest travel in h, from the gathered sphere velocities.
  double CandidateMargin(const State& state, double h) const;
  // What both AdvanceTool and PrepareTool do first: a tool's first active target places its tip,
  // the coupling fades toward on (active) or off, the jaws and orientation follow the target.
  // Returns false for a tool never yet active (nothing more to do); *active: the target's.
  bool FollowTarget(int index, double h, ToolState* ts, bool* active);
  void AdvanceTool(int index, double h, const Points& q, const Points& qd, ToolState* ts);
  // The implicit integrator's counterpart of AdvanceTool: the coupling's fade, the jaws, this
  // sub-step's target path and the grasp; the tip stays where it is (the solve moves it).
  void PrepareTool(int index, double h, const Points& q, ToolState* ts);
  // The tools' capsules and velocities from the state's tips (the geometry follows).
  void SyncTools(const State& state);

  const Model& model_;
  ContactLaw law_;
  double radius_, margin_;
  // The implicit integrator's sub-step: pairs predicted to touch within it act already
  // (speculative contacts); 0 for RK4, which evaluates the true penetration at every stage.
  double speculative_h_ = 0.0;
  // RequiredSubsteps left candidates for the whole step: the first sub-step reuses them.
  bool candidates_fresh_ = false;
  // This sub-step's index and the step's count (from RequiredSubsteps): where the tools' targets
  // are along their way across the step.
  int substep_ = 0, substeps_ = 1;

  ChainKinematics kinematics_;  // the spheres where q puts them, and their velocities
  collision::VerletList candidates_;
  std::vector<Vec3> tool_velocity_;
  Grasps grasps_;  // taken from the state by FollowState, given back to it as they change
  // The candidates' narrow phase, computed once per configuration: RequiredSubsteps, the tools'
  // advance, the force evaluations and EndStep all read it (and EndStep's serves the next step).
  ContactGeometry geometry_;
  // Per force evaluation: each sphere's summed contact stiffness and damping (spread onto its
  // window once, not once per contact).
  std::vector<Mat3> sphere_k_, sphere_d_;
  std::vector<char> sphere_touched_;
  SelfPairCoupling self_pairs_;  // the last AddForces' self pairs (with K)
  ImpactSets impacts_;
  StickSlipFriction friction_;
  // A tool's contacts as its tip cycles see them: each cycle evaluates the contact law again from
  // the sub-step start's geometry and speeds, moved by the tip's own motion since.
  struct TipContact {
    Vec3 normal = Vec3::Zero();    // from the shaft to the sphere
    ShaftLever lever;              // where on the shaft
    double depth = 0.0;            // at the sub-step's start
    Vec3 relative = Vec3::Zero();  // the sphere's velocity minus the shaft point's, at the start
  };
  std::vector<TipContact> tip_contacts_;
  bool tips_in_solve_ = false;
  TipCoupling tips_;  // the tips' rows in the implicit solve
  HapticOutput haptic_;
};

}  // namespace viscera::mechanics
