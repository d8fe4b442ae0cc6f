#pragma once
/// A read-only view of the last sub-step's linear system in an ImplicitEulerIntegrator, for
/// what solves that system otherwise (bench/exact_system.h assembles it for direct solvers,
/// bench_direct_coupling reruns its CG with other preconditioners, and their tests). The step
/// itself needs none of it: kept out of the integrator's public interface, which is what a
/// stepper uses, and valid only after Advance, until the next one.
#include "mechanics/implicit_euler.h"

namespace viscera::mechanics {

class ImplicitSystemView {
 public:
  explicit ImplicitSystemView(const ImplicitEulerIntegrator& integrator)
      : integrator_(integrator) {}

  /// The band system P = M + ĥ D + ĥ^2 K with each self pair as 2 H per side; the global
  /// stretching energy's rank-one term w u u^T (w = 0: none); the right-hand side b. The exact
  /// matrix is P + w u u^T minus the pairs' common modes (MultiplyExact).
  const BlockBand& band_system() const { return integrator_.band_.system(); }
  double rank_one_weight() const { return integrator_.corrections_.weight(); }
  const Points& rank_one_u() const { return integrator_.jac_.rank1_u; }
  const VecX& last_rhs() const { return integrator_.b_; }
  /// y = A x for the exact matrix (the pairs' common modes as Interactions last weighed them:
  /// after Advance, with (ĥ^2, ĥ)).
  void MultiplyExact(const Eigen::Ref<const VecX>& x, VecX* y) const {
    integrator_.MultiplyExact(x, y);
  }
  /// The CG stop (on r^T M^-1 r, M the preconditioner). Its correction (exact answer minus the
  /// band's) and the one before are the state's (State::cg_correction,
  /// cg_previous_correction): the next coupled sub-step starts from the band's answer plus
  /// twice the one minus the other.
  double last_cg_stop() const { return integrator_.last_cg_stop_; }

 private:
  const ImplicitEulerIntegrator& integrator_;
};

}  // namespace viscera::mechanics
