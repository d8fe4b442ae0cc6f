#include "mechanics/implicit_euler.h"

#include <algorithm>
#include <limits>

#include "common/check.h"
#include "mechanics/banded_cholesky.h"
#include "mechanics/interactions.h"
#include "mechanics/linearization_guard.h"
#include "mechanics/mass_solver.h"

namespace viscera::mechanics {

ImplicitEulerIntegrator::ImplicitEulerIntegrator(const Model& model, Interactions* interactions)
    : model_(model),
      interactions_(interactions),
      n_(model.num_points()),
      guard_(model.params().linearization_guard),
      // BDF2 steps where the impact and depth constraints would not act, and backward Euler
      // where they would: without them (the limiter alone) nothing tells, and a landed pile
      // stepped by BDF2 gained energy (docs/integrators.md).
      bdf2_(model.params().implicit_scheme == ImplicitScheme::kBdf2 &&
            (interactions == nullptr || model.params().contacts.impact_constraints)),
      // Stick-slip friction with the impact and depth constraints, as BDF2: held by the limiter
      // alone, a jammed pile's stuck pairs were pushed deep in a 100 Hz step and gained energy.
      stick_slip_(interactions != nullptr &&
                  model.params().contacts.friction_law == FrictionLaw::kStickSlip &&
                  model.params().contacts.impact_constraints),
      band_(model.num_points(), model.params().linear_solver == LinearSolverKind::kCholmod),
      corrections_(model),
      end_(model, interactions, [this](double* x) { ApplyBandInverse(x); }),
      tips_(model.num_points(), static_cast<int>(model.params().tools.size()), interactions),
      friction_(model.num_points(), interactions, stick_slip_,
                [this](double* x) { ApplyBandInverse(x); }) {
  gravity_floor_share_ = stick_slip_ ? kStickSlipGravityFloor : 1.0;
  scratch_.Resize(n_);
  jac_.Resize(n_);
  force_.setZero(n_, 3);
  kv_.setZero(n_, 3);
  step_dq_.setZero(n_, 3);
  history_.setZero(n_, 3);
  // m |g|^2 = |total weight| |g|: the generalized weight W satisfies M^-1 W = g at every point.
  const Eigen::Vector3d weight = model.gravity_force().colwise().sum().transpose();
  weight_scale_ = weight.norm() * model.params().gravity.norm();
  b_.setZero(3 * n_);
  cg_.Resize(3 * n_);
  tip_columns_.reserve(3 * model.params().tools.size());
  tip_first_.reserve(3 * model.params().tools.size());
}

void ImplicitEulerIntegrator::AddHistory(const StepWeights& w, const State& state) {
  // K Δq as K v was taken: the band, the rank-one part, without the self pairs' common modes.
  jac_.stiffness.Multiply(state.last_dq, &history_);
  const double c = jac_.rank1_coeff;
  if (c > 0.0)
    history_ += (c * (jac_.rank1_u.array() * state.last_dq.array()).sum()) * jac_.rank1_u;
  if (interactions_ != nullptr && interactions_->coupled_pairs() > 0)
    interactions_->AddCommonModeTerms(state.last_dq, &history_);
  b_ -= (w.history * w.h_eff) * Eigen::Map<const VecX>(history_.data(), 3 * n_);
  BandMultiply(model_.mass_band(), state.last_dqd, &history_);
  b_ += w.history * Eigen::Map<const VecX>(history_.data(), 3 * n_);
}

void ImplicitEulerIntegrator::ApplyBandInverse(double* x) {
  band_.SolveInPlace(x);
  ApplyCorrections(x);
}

void ImplicitEulerIntegrator::ApplyCorrections(double* x) {
  corrections_.Apply(x, jac_.rank1_u);
  if (tips_.woodbury()) tips_.ApplyCorrection(x);
}

void ImplicitEulerIntegrator::MultiplyExact(const Eigen::Ref<const VecX>& x, VecX* y) const {
  // The band and the common modes read 3N values as #N by 3 points: the same storage.
  VISCERA_ASSERT(x.size() == 3 * n_ && x.data() != y->data());
  y->resize(3 * n_);
  band_.system().Multiply(x.data(), y->data());
  if (interactions_) interactions_->AddCommonModeTerms(x.data(), y->data());
  friction_.AddTerms(x.data(), y->data());
  if (tips_.woodbury()) tips_.SubtractSchur(x.data(), y->data());
  if (const double w = corrections_.weight(); w > 0.0) {
    Eigen::Map<const VecX> u(jac_.rank1_u.data(), 3 * n_);
    *y += (w * u.dot(x)) * u;
  }
}

bool ImplicitEulerIntegrator::RefineExactly(const VecX& b, double h, Eigen::Ref<VecX> dv,
                                            State* state, bool again, bool linked) {
  // Preconditioned CG on A dv = b, restricted to the pins' null space by the preconditioner
  // (every direction is a preconditioned residual). It starts from the band's answer plus the
  // correction extrapolated from the last two sub-steps': between 1 kHz steps the contacts
  // barely change, so that start is most of the way (the last correction alone took 2.5
  // iterations per 1 kHz step of the clearing gesture, its linear extrapolation 1.8; a quadratic
  // one 2.1; docs/self-coupling.md). It stops when the preconditioned residual is a small
  // fraction of b's, or of gravity's impulse over the sub-step when b is smaller: in a resting
  // pile the forces nearly cancel (the cavity's median b is 0.2 % of gravity's impulse, in this
  // norm), and a fraction of b asked for velocities exact to a tenth of a micrometre per second
  // (settled fall: 10.7 iterations per sub-step, 3.4 with the floor; docs/self-coupling.md).
  // (h W)^T M^-1 (h W) is m (h g)^2. Under stick-slip friction the floor is lowered to a share of
  // that (a resting pile's stuck springs), but not while a tool's tip is linked to the tube.
  const double share = linked ? linked_floor_share_ : gravity_floor_share_;
  const double gravity_reference = share * share * h * h * weight_scale_;
  const double reference =
      std::max(b.dot(dv), gravity_reference);  // b^T P^-1 b: dv is the band's answer
  const double stop = kCgTolerance * kCgTolerance * reference;
  last_cg_stop_ = stop;
  VecX& correction = state->cg_correction;
  WarmStart(again, state);
  dv += correction;
  const int cap = model_.params().cg_iteration_cap > 0 ? model_.params().cg_iteration_cap
                                                       : kMaxCgIterationsExtended;
  const PreconditionedCg::Result result =
      cg_.Solve([this](const Eigen::Ref<const VecX>& x, VecX* y) { MultiplyExact(x, y); },
                [this](VecX* x) { ApplyBandInverse(x->data()); }, b, stop, cap, dv, &correction);
  if (result.iterations > kMaxCgIterations) ++counts_.cg_extended;
  last_cg_iterations_ = result.iterations;
  counts_.cg_iterations += result.iterations;
  return result.converged;
}

void ImplicitEulerIntegrator::WarmStart(bool again, State* state) const {
  // The warm start is the state's (State::cg_correction): a step from a copied state starts from
  // the same guess whatever this integrator solved before.
  VecX& correction = state->cg_correction;
  VecX& previous = state->cg_previous_correction;
  if (correction.size() != 3 * n_ || previous.size() != 3 * n_) {
    correction.setZero(3 * n_);  // a state not made by InitialState: allocates, once
    previous.setZero(3 * n_);
  }
  if (again) return;
  // correction + (correction - previous), the last one kept as the previous.
  for (Eigen::Index i = 0; i < correction.size(); ++i) {
    const double step = correction(i) - previous(i);
    previous(i) = correction(i);
    correction(i) += step;
  }
}

void ImplicitEulerIntegrator::ClearTipReleases() {
  tips_.ClearRounds();
  friction_rounds_ = 0;
  if (interactions_ != nullptr) interactions_->ClearTipReleases();
}

void ImplicitEulerIntegrator::Advance(std::span<const PointLoad> loads, double h, State* state) {
  ClearTipReleases();
  AdvanceHalving(loads, h, 0, std::numeric_limits<double>::infinity(), bdf2_, state);
  if (stick_slip_) interactions_->UseFriction(nullptr, 0.0);  // State::friction may move
}

void ImplicitEulerIntegrator::AdvanceHalves(std::span<const PointLoad> loads, double h,
                                            int halvings, double unseen, State* state) {
  const double end = tip_end_, span = tip_span_;  // the tools' targets: half the way each
  tip_span_ = 0.5 * span;
  tip_end_ = end - tip_span_;
  ClearTipReleases();
  AdvanceHalving(loads, 0.5 * h, halvings + 1, unseen, bdf2_, state);
  tip_end_ = end;
  ClearTipReleases();
  AdvanceHalving(loads, 0.5 * h, halvings + 1, unseen, bdf2_, state);
  tip_span_ = span;
}

void ImplicitEulerIntegrator::AdvanceHalving(std::span<const PointLoad> loads, double h,
                                             int halvings, double parent_unseen, bool bdf2,
                                             State* state) {
  Points& q = state->q;
  Points& v = state->qd;
  const bool again = solving_again_;
  solving_again_ = false;
  ++counts_.substeps;
  const bool tips = tips_.Present(*state);
  friction_.Clear();
  if (tips) interactions_->PlaceTips(*state, tip_end_);
  if (stick_slip_) interactions_->UseFriction(&state->friction, h);
  ComputeForces(model_, q, v, loads, &scratch_, &force_, nullptr, &jac_, interactions_);
  // BDF2 builds on the last sub-step when it had this length (a halving, a change of the step's
  // sub-steps, an impulse or a reset leave it nothing to build on). The tips' rows are backward
  // Euler's: a sub-step in which a tip touches or holds the tube is one too; a tip that touches
  // nothing moves alone, and the tube's rows may be BDF2's.
  const bool tips_linked = tips && !interactions_->tip_links().empty();
  const bool multistep = bdf2 && !tips_linked && state->last_h == h &&
                         state->last_dq.rows() == n_ && state->last_dqd.rows() == n_;
  const StepWeights w = multistep ? Bdf2(h) : BackwardEuler(h);
  const bool coupled = interactions_ != nullptr && interactions_->coupled_pairs() > 0;

  // b = ĥ (F - ĥ K v) (+ BDF2's history), K including the rank-one part c u (u . v) and without
  // the band's excess on self pairs' common motion.
  jac_.stiffness.Multiply(v, &kv_);
  const double c = jac_.rank1_coeff;
  if (c > 0.0) kv_ += (c * (jac_.rank1_u.array() * v.array()).sum()) * jac_.rank1_u;
  if (coupled) {
    interactions_->WeighCommonModes(-1.0, 0.0);
    interactions_->AddCommonModeTerms(v, &kv_);
  }
  if (tips) tips_.AddStiffness(*state, &kv_);
  Eigen::Map<const VecX> force_flat(force_.data(), 3 * n_);
  Eigen::Map<const VecX> kv_flat(kv_.data(), 3 * n_);
  b_ = w.h_eff * (force_flat - w.h_eff * kv_flat);
  if (multistep) AddHistory(w, *state);
  tips_.Reset();
  if (tips) tips_.Reduce(h, &b_);
  corrections_.Load(b_, jac_.rank1_u);

  band_.Assemble(model_.mass_band(), jac_, w.h_eff, w.stiffness);
  if (!band_.Factor()) {
    // Cannot happen for M + ĥ D + ĥ^2 K with K, D clamped PSD; count it and take an explicit
    // step rather than produce garbage.
    ++counts_.factorization_failures;
    MassSolver fallback(model_);
    fallback.SolveConstrainedInPlace(&force_);  // allocates, but this path is an error
    v += h * force_;
    q += h * v;
    if (tips) {
      tips_.Reset();  // the tips unlinked: their own rows only
      b_.setZero();
      tips_.Solve(h, v, b_.data(), *state);  // the tips alone, against their own rows
      tips_.Advance(h, nullptr, state);
    }
    state->last_h = 0.0;
    return;
  }
  // Columns 1.. (z = A^-1 u, Y = A^-1 G^T) once, column 1 only with a rank-one term; column 0
  // then gets their corrections.
  // The tips' Woodbury columns (Y = P^-1 B) are solved with them.
  corrections_.SetWeight(w.stiffness * c);
  tip_columns_.clear();
  tip_first_.clear();
  if (tips) tips_.LoadColumns(&tip_columns_, &tip_first_);
  band_.SolveColumns(&corrections_.columns(), corrections_.first_solved(), tip_columns_,
                     tip_first_);
  auto dv = corrections_.columns().col(0);
  corrections_.Prepare(jac_.rank1_u);
  if (tips) tips_.PrepareCorrection([this](double* x) { ApplyCorrections(x); });
  ApplyCorrections(dv.data());
  last_cg_iterations_ = 0;
  bool converged = true;
  if (coupled) {
    interactions_->WeighCommonModes(-w.stiffness, -w.h_eff);
    converged = RefineExactly(b_, h, dv, state, again, tips_linked);
  } else {
    state->cg_correction.setZero();
    state->cg_previous_correction.setZero();
  }
  const auto dv_points = Eigen::Map<const Points>(dv.data(), n_, 3);
  // Each round ends the sub-step: done otherwise (as halves, as backward Euler, or evaluated
  // again), accepted, or, for contacts whose friction was revised, solved again from their change
  // alone (the next round).
  for (;;) {
    if (!converged) {
      // A solve that did not converge: the sub-step again as two halves (each nearer the
      // last, better conditioned), or, at the deepest halving, accepted and counted.
      if (halvings < kMaxHalvings) {
        ++counts_.cg_halved;
        AdvanceHalves(loads, h, halvings, std::numeric_limits<double>::infinity(), state);
        return;
      }
      ++counts_.cg_unconverged;
      ++state->unconverged_solves;
    }
    if (multistep) {
      step_dq_ = w.history * state->last_dq + w.h_eff * (v + dv_points);
      // Done again as backward Euler: a sub-step that leaves more unseen stretch than a tenth of
      // the guard's (BDF2 builds on the last sub-step's motion and gives that stretch back as
      // energy, which backward Euler's damping absorbs: a stretched hairpin snapping straight
      // gained 0.9 % of its energy in a step at 500 Hz), and one that needs impact or depth
      // constraints (they hold the end velocity and let it move q by h v', backward Euler's
      // kinematics; BDF2's motion would keep a third of the last sub-step's closing).
      const bool stretched =
          stretch_redo_ && !LinearizationGuard::UnseenStretchWithin(
                               q, step_dq_, LinearizationGuard::kMaxUnseenStretchBdf2);
      if (stretched || (impact_redo_ && end_.Needed(h, step_dq_))) {
        ++(stretched ? counts_.stretch_redos : counts_.impact_redos);
        --counts_.substeps;
        AdvanceHalving(loads, h, halvings, parent_unseen, false, state);
        return;
      }
    }
    // Impacts and depth held inside the solve: backward Euler's (a BDF2 sub-step that needs them
    // was done again above).
    const int64_t impacts_before = end_.substeps();
    const bool correct_depth = multistep ? false : end_.Resolve(h, v, dv);
    const bool end_held = end_.substeps() != impacts_before;  // impulses or a depth correction
    if (tips && tips_.Solve(h, v, dv.data(), *state)) {
      tips_.CountRound();  // a tip contact would pull, or is stiffer where it ends: solved again
      ++counts_.tip_redos;
      solving_again_ = coupled;
      AdvanceHalving(loads, h, halvings, parent_unseen, bdf2, state);
      return;
    }
    if (stick_slip_ && friction_rounds_ < kMaxFrictionRounds &&
        interactions_->ReviseFriction(v, dv.data(), tips ? tips_.dv().data() : nullptr)) {
      ++friction_rounds_;  // a contact sticks or slides otherwise than solved: solved again
      ++counts_.friction_redos;
      // Only the revised pairs' terms change: with the exact coupling's CG, and no impulse in the
      // solve (the impulses' columns are the band's, which keeps the evaluation's pairs), the
      // solve takes them as a change of b and of the exact matrix, from the last answer.
      if (friction_.enabled() && coupled && !end_held &&
          friction_.TakeRevisions(w.h_eff, w.stiffness, w.history, &b_, dv, state)) {
        converged = RefineExactly(b_, h, dv, state, true, tips_linked);
        continue;
      }
      solving_again_ = coupled;
      AdvanceHalving(loads, h, halvings, parent_unseen, bdf2, state);
      return;
    }
    // The step is one linearization: a segment turned far within it stretches by what the linear
    // model cannot see (a slack tube pulled sideways has no sideways stiffness to first order), and
    // that stretch returns as energy nobody put in. Such a sub-step is done again as two halves.
    if (guard_ && halvings < kMaxHalvings) {
      if (!multistep) step_dq_ = h * (v + dv_points);  // BDF2's is already there
      if (correct_depth) step_dq_ += h * Eigen::Map<const Points>(end_.depth_dq().data(), n_, 3);
      // Halving shrinks what the velocities and the forces move (4 to 16 times).
      const double unseen = LinearizationGuard::Excess(q, step_dq_);
      if (LinearizationGuard::Halve(unseen, halvings, parent_unseen)) {
        ++counts_.halved_substeps;
        AdvanceHalves(loads, h, halvings, unseen, state);
        return;
      }
    }
    if (multistep) {
      ++counts_.bdf2_substeps;
      q += step_dq_;
      state->last_dq = step_dq_;
    } else {
      state->last_dq = q;  // then its motion, below
    }
    state->last_dqd = dv_points;
    // An impulse or a position correction is not a motion to build on.
    state->last_h = end_held ? 0.0 : h;
    if (multistep) {
      if (tips) tips_.Advance(h, nullptr, state);  // touching nothing: their own backward Euler
      Eigen::Map<VecX>(v.data(), 3 * n_) += dv;
      if (stick_slip_) interactions_->AdvanceFriction(step_dq_, h, state);
      return;
    }
    // Not q += step_dq_: q + h v' + h depth_dq, in that order, rounds as the step did before the
    // guard existed (and as it does with the guard off).
    if (tips) tips_.Advance(h, correct_depth ? &end_.depth_dq() : nullptr, state);
    Eigen::Map<VecX>(v.data(), 3 * n_) += dv;
    q += h * v;
    if (correct_depth) q += h * Eigen::Map<const Points>(end_.depth_dq().data(), n_, 3);
    state->last_dq = q - state->last_dq;
    if (stick_slip_) interactions_->AdvanceFriction(state->last_dq, h, state);
    return;
  }
}

}  // namespace viscera::mechanics
