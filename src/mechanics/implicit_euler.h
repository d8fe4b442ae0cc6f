#pragma once
/// Linearly implicit (semi-implicit) backward Euler, as in Baraff & Witkin 1998:
///   (M + h D + h^2 K) dv = h (F(q, v) - h K v),   v' = v + dv,   q' = q + h v',
/// with K = -dF/dq, D = -dF/dv and M the mass matrix acting on each axis, or by default its
/// second-order sibling BDF2, which also reads the last sub-step (State::last_dq, last_dqd) and
/// takes the same system with 2h/3 for h (StepWeights; docs/mechanics.md). The 3N unknowns are
/// ordered x0 y0 z0 x1 ...; the matrix is block banded (|i - j| <= 3) and is factored either by
/// a 3x3 block-band Cholesky or by CHOLMOD, whose symbolic analysis is done once and reused
/// while the pattern holds (params().linear_solver; the faster is the default). The global
/// stretching energy's dense rank-one stiffness is applied by Sherman-Morrison, and the pins are
/// solved inside the system (Schur complement), all from one multi-column CHOLMOD solve.
/// Self-contacts couple windows far apart in the chain: the band holds them approximately (an
/// upper bound, see Interactions::AddForces), and preconditioned conjugate gradients on the
/// exact matrix, with that band solve as the preconditioner, removes the difference (the pair's
/// artificial drag on common motion). docs/self-coupling.md: why CG and what it costs.
/// Both are unconditionally stable for the linearized system and damp high frequencies; backward
/// Euler also damps a slow mode of frequency ω by h ω² / 2 (1/s), BDF2 by O(h³ ω⁴).
#include <vector>

#include "mechanics/band_corrections.h"
#include "mechanics/band_system_solver.h"
#include "mechanics/conjugate_gradient.h"
#include "mechanics/end_constraints.h"
#include "mechanics/friction_resolve.h"
#include "mechanics/integrator.h"
#include "mechanics/interactions.h"
#include "mechanics/tip_schur.h"

namespace viscera::mechanics {

class ImplicitEulerIntegrator final : public Integrator {
 public:
  explicit ImplicitEulerIntegrator(const Model& model, Interactions* interactions = nullptr);
  void Advance(std::span<const PointLoad> loads, double h, State* state) override;

  /// The scheme's coefficients for one sub-step of h, with Δq, Δv the last sub-step's motion and
  /// change of velocity (State::last_dq, last_dqd):
  ///   (M + ĥ D + ĥ² K) dv = ĥ (F - ĥ K v) + μ (M Δv - ĥ K Δq),   v' = v + dv,   q' = q + μ Δq + ĥ
  ///   v'.
  /// Backward Euler: ĥ = h, μ = 0. BDF2 (q' = (4 q - q_prev) / 3 + (2h/3) v', the same for v and
  /// M v' - (2h/3) F(q', v')), linearized at (q, v): ĥ = 2h/3, μ = 1/3.
  struct StepWeights {
    double h_eff;      // ĥ: D's weight in the matrix, F's in b, v''s in q'
    double stiffness;  // ĥ²: K's weight in the matrix
    double history;    // μ: the last sub-step's share of b and q'
  };
  static StepWeights BackwardEuler(double h) { return {h, h * h, 0.0}; }
  static StepWeights Bdf2(double h) { return {2.0 * h / 3.0, 4.0 * h * h / 9.0, 1.0 / 3.0}; }
  /// Sub-steps whose BDF2 step would have needed impact or depth constraints, done again as
  /// backward Euler, whose end velocity moves q as those constraints assume.
  int64_t impact_redos() const { return counts_.impact_redos; }
  /// BDF2 sub-steps whose motion its linearization saw too little of
  /// (LinearizationGuard::kMaxUnseenStretchBdf2), done again as backward Euler.
  int64_t stretch_redos() const { return counts_.stretch_redos; }
  /// Whether that is done (on by default; off only to show it is needed, in tests).
  void set_stretch_redo(bool on) { stretch_redo_ = on; }
  /// Solves done again because a contact's stick or slip was revised
  /// (Interactions::ReviseFriction), and those of them done without evaluating the sub-step again.
  int64_t friction_redos() const { return counts_.friction_redos; }
  int64_t friction_resolves() const { return friction_.resolves(); }
  /// Whether a revised contact is solved again from the change of its terms alone (on by
  /// default; off, the sub-step is evaluated again: to compare the two, in tests).
  void set_friction_resolve(bool on) { friction_.set_enabled(on); }
  /// Solves done again because a tip contact would pull or is stiffer where it ends.
  int64_t tip_redos() const { return counts_.tip_redos; }
  /// Sub-steps taken as BDF2.
  int64_t bdf2_substeps() const { return counts_.bdf2_substeps; }
  /// Whether that is done (on by default; off only to show it is needed, in tests).
  void set_impact_redo(bool on) { impact_redo_ = on; }
  /// Whether impulses and depth corrections between parts of the tube, held inside the solve,
  /// are kept from the momentum that the band system they act through gives them (it ties each
  /// side of a self pair to the world; EndConstraints::KeepPairsMomentum). On by default; off only
  /// to show it is needed, in tests.
  void set_impact_momentum_kept(bool on) { end_.set_momentum_kept(on); }

  /// Steps whose matrix CHOLMOD found not positive definite (the step then falls back to a
  /// damped explicit update). Should stay 0.
  int64_t factorization_failures() const { return counts_.factorization_failures; }
  /// Conjugate-gradient iterations of the last sub-step (0 without self pairs), and in all.
  int last_cg_iterations() const { return last_cg_iterations_; }
  int64_t cg_iterations() const { return counts_.cg_iterations; }
  /// Sub-steps advanced so far.
  int64_t substeps() const { return counts_.substeps; }
  /// Sub-steps accepted with a CG that stopped at kMaxCgIterationsExtended before reaching
  /// kCgTolerance, even at the deepest halving (also counted in State::unconverged_solves).
  int64_t cg_unconverged() const { return counts_.cg_unconverged; }
  /// CG stops when the preconditioned residual norm falls below this fraction of b's, or of the
  /// sub-step's gravity impulse h W (in M^-1's norm, m (h g)^2: an RMS over the tube's mass) when
  /// that is larger (docs/self-coupling.md: 1e-3 keeps a moving block's mass within 0.1 %, in ~1-3
  /// iterations at 1 kHz).
  static constexpr double kCgTolerance = 1e-3;
  /// With stick-slip friction, the share of gravity's impulse over the sub-step at which CG's
  /// stop is floored (set_gravity_floor; the whole impulse under the regularized law). Held by
  /// static friction, a resting pile is a network of springs that a looser stop's residual sets
  /// jittering: floored at the whole impulse, the shipped fall's pile gained up to 5e-9 J in a step
  /// at 250 Hz; at 0.3 it rests and gains nothing beyond round-off, and the clearing gesture costs
  /// the same. A pile that slides under viscous friction damps the residual.
  static constexpr double kStickSlipGravityFloor = 0.3;
  /// The share while a tool's tip is linked to the tube in the solve (kLinkedGravityFloor): the
  /// hand drives the tube, no resting network of stuck springs, and the whole impulse's stop
  /// saves CG a sixth of its iterations on the clearing gesture (3.99 per 100 Hz sub-step and
  /// 1.10 per 1 kHz step, against 4.82 and 1.32 at 0.3).
  static constexpr double kLinkedGravityFloor = 1.0;
  static constexpr int kMaxCgIterations = 60;
  /// A solve still short of kCgTolerance after kMaxCgIterations goes on to this many; still
  /// short, its sub-step is done again as two halves (as the linearization guard does, at most
  /// kMaxHalvings deep); still short at that depth, it is accepted and counted (cg_unconverged).
  /// ModelParams::cg_iteration_cap lowers it (tests).
  static constexpr int kMaxCgIterationsExtended = 4 * kMaxCgIterations;
  /// Solves that needed more than kMaxCgIterations, and sub-steps halved because a solve did not
  /// converge within kMaxCgIterationsExtended, in all.
  int64_t cg_extended() const { return counts_.cg_extended; }
  int64_t cg_halved() const { return counts_.cg_halved; }
  /// The share of the gravity impulse below whose kCgTolerance CG's stop also accepts a residual
  /// (kStickSlipGravityFloor or 1 by default, kLinkedGravityFloor while a tip is linked; 0 turns
  /// the floor off, to compare against the stricter stop in tests and benchmarks). Sets both.
  void set_gravity_floor(double share) { gravity_floor_share_ = linked_floor_share_ = share; }
  /// Sub-steps done again as two halves (by LinearizationGuard, or for a CG that did not
  /// converge) nest at most this deep.
  static constexpr int kMaxHalvings = 5;
  /// Sub-steps the linearization guard did again as two halves, in all.
  int64_t halved_substeps() const { return counts_.halved_substeps; }
  /// Sub-steps whose solve needed impulses (impacts held inside it), and those impulses'
  /// contacts in all (docs/impacts.md).
  int64_t impact_substeps() const { return end_.substeps(); }
  int64_t impact_contacts() const { return end_.contacts(); }

 private:
  friend class ImplicitSystemView;  // the last sub-step's system, read-only (bench, tests)

  // Advance, done again as two halves (recursively) when the sub-step turns a segment too far;
  // parent_unseen: the unseen stretch of the sub-step these are halves of (infinite at the top).
  // bdf2: whether this sub-step may be BDF2 (the scheme's, unless done again for its impacts).
  void AdvanceHalving(std::span<const PointLoad> loads, double h, int halvings,
                      double parent_unseen, bool bdf2, State* state);
  // The sub-step of length h done as two halves (the tools' targets half the way each).
  void AdvanceHalves(std::span<const PointLoad> loads, double h, int halvings, double unseen,
                     State* state);
  // b_ += μ (M Δv - ĥ K Δq) (BDF2); kv_'s common modes still weighed as for K v.
  void AddHistory(const StepWeights& w, const State& state);
  // x <- the solution of the band system with the rank-one term and the pins (the preconditioner).
  void ApplyBandInverse(double* x);
  // x <- from the band system's solution to that of the preconditioner (rank one, pins).
  void ApplyCorrections(double* x);
  // y = A x for the last sub-step's exact matrix: the band's system, its rank-one term, minus
  // the common modes (as Interactions last weighed them), minus the tips' B C^-1 B'.
  void MultiplyExact(const Eigen::Ref<const VecX>& x, VecX* y) const;
  // Refines dv (the band system's answer to b) toward the exact matrix's by preconditioned CG.
  // Returns whether it reached kCgTolerance (within kMaxCgIterationsExtended). Starts from, and
  // updates, the state's warm start.
  // `again`: the sub-step solved again (a contact's mode revised): CG starts from the last
  // solve's correction, and the extrapolation the next sub-step makes is left as it was.
  // `linked`: a tool's tip is linked to the tube (the stop's floor is linked_floor_share_).
  bool RefineExactly(const VecX& b, double h, Eigen::Ref<VecX> dv, State* state, bool again,
                     bool linked);
  // The state's correction <- CG's start (added to the band's answer): twice the last correction
  // minus the one before, which becomes the last; left as it was when `again`.
  void WarmStart(bool again, State* state) const;
  void ClearTipReleases();  // a new sub-step (or half): every tip and friction contact acts again
  // Solves of one sub-step redone while its contacts' stick or slip is revised
  // (Interactions::ReviseFriction).
  static constexpr int kMaxFrictionRounds = 3;
  bool solving_again_ = false;  // the next AdvanceHalving solves the last sub-step again

  const Model& model_;
  Interactions* interactions_;
  int n_;                        // control points
  bool guard_;                   // params().linearization_guard
  bool bdf2_;                    // params().implicit_scheme is BDF2, with impact constraints
  bool stick_slip_;              // contacts with stick-slip friction (State::friction's anchors)
  BandSystemSolver band_;        // M + ĥ D + ĥ^2 K
  BandCorrections corrections_;  // its rank-one term and the pins, through its solves
  StretchScratch scratch_;
  ForceJacobians jac_;
  Points force_, kv_;
  Points history_;  // K Δq, then M Δv (AddHistory)
  Points step_dq_;  // the sub-step's motion, checked before it is accepted
  VecX b_;          // the right-hand side
  PreconditionedCg cg_;
  EndConstraints end_;  // impacts and depth held inside the solve, through the band system
  double gravity_floor_share_;
  double linked_floor_share_ = kLinkedGravityFloor;
  bool impact_redo_ = true;
  double weight_scale_ = 0.0;  // m |g|^2, m the whole tube's mass
  int last_cg_iterations_ = 0;
  double last_cg_stop_ = 0.0;
  // The tools' tips, three unknowns per tool, eliminated from the solve. Their targets' path is
  // followed to tip_end_ (fraction of the sub-step) over a span tip_span_ (halvings split it).
  TipSchur tips_;
  // The tips' Woodbury columns for this sub-step's band solve (TipSchur::LoadColumns).
  std::vector<double*> tip_columns_;
  std::vector<int> tip_first_;
  int friction_rounds_ = 0;
  FrictionResolve friction_;  // a revised contact's solve done again from its change of terms
  double tip_end_ = 1.0, tip_span_ = 1.0;
  bool stretch_redo_ = true;
  // What the solves did since the start (the counters above read them).
  struct Counts {
    int64_t factorization_failures = 0, cg_iterations = 0, cg_unconverged = 0, substeps = 0;
    int64_t halved_substeps = 0, cg_extended = 0, cg_halved = 0, impact_redos = 0;
    int64_t bdf2_substeps = 0, friction_redos = 0, stretch_redos = 0, tip_redos = 0;
  } counts_;
};

}  // namespace viscera::mechanics
