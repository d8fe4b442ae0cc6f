#pragma once
/// Preconditioned conjugate gradients on A x = b, A symmetric positive definite and given only
/// as a product, M^-1 (the preconditioner, also symmetric positive definite) only as an
/// in-place solve. It is the iteration without its problem: the caller chooses the start (x on
/// entry), the stop (a bound on r^T M^-1 r) and the cap on iterations, so that the implicit
/// step's warm start and its floor under the stop (ImplicitEulerIntegrator::RefineExactly) stay
/// with the step, and the benchmarks' and the step's CG are one algorithm. Its four vectors are
/// kept between solves (Resize once): a solve allocates nothing, as the step must not.
#include <algorithm>

#include "common/types.h"

namespace viscera::mechanics {

class PreconditionedCg {
 public:
  struct Result {
    int iterations;
    bool converged;  // r^T M^-1 r at most the stop
  };

  /// Sizes the vectors for n unknowns.
  void Resize(Eigen::Index n) {
    for (VecX* v : {&r_, &z_, &p_, &q_}) v->setZero(n);
  }

  /// Refines x toward A^-1 b from its value, until r^T M^-1 r <= stop, after max_iterations,
  /// or when p^T A p is not positive (A is positive definite: round-off at convergence).
  /// multiply(const Eigen::Ref<const VecX>& x, VecX* y): y = A x (y never aliases x);
  /// precondition(VecX* x): x <- M^-1 x. `steps`, when not null, receives x's changes as well
  /// (a caller that keeps x minus a reference of its own).
  template <typename Multiply, typename Precondition>
  Result Solve(Multiply&& multiply, Precondition&& precondition, const VecX& b, double stop,
               int max_iterations, Eigen::Ref<VecX> x, VecX* steps) {
    multiply(x, &q_);
    r_ = b - q_;
    return Continue(multiply, precondition, stop, 0.0, max_iterations, x, steps);
  }

  /// Solve from x whose residual b - A x is already residual(); the stop is also at least
  /// relative^2 times the start's r^T M^-1 r. residual() is the end's on return.
  template <typename Multiply, typename Precondition>
  Result Continue(Multiply&& multiply, Precondition&& precondition, double stop, double relative,
                  int max_iterations, Eigen::Ref<VecX> x, VecX* steps) {
    z_ = r_;
    precondition(&z_);
    double rz = r_.dot(z_);
    stop = std::max(stop, relative * relative * rz);
    p_ = z_;
    int it = 0;
    while (it < max_iterations && rz > stop) {
      ++it;
      multiply(p_, &q_);
      const double pq = p_.dot(q_);
      if (!(pq > 0.0)) break;
      const double alpha = rz / pq;
      x += alpha * p_;
      if (steps != nullptr) *steps += alpha * p_;
      r_ -= alpha * q_;
      z_ = r_;
      precondition(&z_);
      const double rz_next = r_.dot(z_);
      p_ = z_ + (rz_next / rz) * p_;
      rz = rz_next;
    }
    return {it, !(rz > stop)};
  }

  VecX& residual() { return r_; }

 private:
  VecX r_, z_, p_, q_;  // residual, preconditioned residual, direction, A p
};

}  // namespace viscera::mechanics
