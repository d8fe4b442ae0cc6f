#include "mechanics/stability.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

#include "mechanics/forces.h"
#include "mechanics/mass_solver.h"

namespace viscera::mechanics {
namespace {

// Largest eigenvalue of M^-1 A (A symmetric PSD, plus c u u^T) on the pins' constraint space,
// by Lanczos in the M inner product with full re-orthogonalization. M^-1 A is self-adjoint in
// that inner product; Lanczos finds the top of a clustered spectrum (a chain's) in tens of
// iterations where power iteration stalls below it.
double LargestEigenvalue(const Model& model, const BlockBand& a, const Points& u, double c) {
  const int n = model.num_points();
  const int steps = std::min(3 * n, 80);
  MassSolver mass(model);
  std::vector<Points> v(steps + 1, Points::Zero(n, 3)), mv(steps + 1, Points::Zero(n, 3));
  // A fixed, non-smooth start, projected onto the constraints (x = P M^-1 M x).
  Points x(n, 3), y(n, 3);
  for (int i = 0; i < n; ++i)
    x.row(i) << (i % 2 ? 1.0 : -1.0), (i % 3 ? 0.7 : -0.4), (i % 5 ? 0.3 : -1.1);
  BandMultiply(model.mass_band(), x, &y);
  mass.SolveConstrainedInPlace(&y);
  auto m_dot = [](const Points& p, const Points& mq) { return (p.array() * mq.array()).sum(); };
  BandMultiply(model.mass_band(), y, &mv[0]);
  const double norm0 = std::sqrt(m_dot(y, mv[0]));
  if (!(norm0 > 0.0)) return 0.0;
  v[0] = y / norm0;
  mv[0] /= norm0;
  VecX alpha = VecX::Zero(steps), beta = VecX::Zero(steps);
  int k = 0;
  for (; k < steps; ++k) {
    a.Multiply(v[k], &y);
    if (c > 0.0) y += (c * (u.array() * v[k].array()).sum()) * u;
    mass.SolveConstrainedInPlace(&y);  // y = P M^-1 A v_k
    alpha(k) = m_dot(y, mv[k]);
    for (int pass = 0; pass < 2; ++pass) {
      for (int i = 0; i <= k; ++i) y -= m_dot(y, mv[i]) * v[i];
    }
    BandMultiply(model.mass_band(), y, &x);
    const double b = std::sqrt(std::max(0.0, m_dot(y, x)));
    if (k + 1 == steps || b <= 1e-12 * std::max(1.0, std::abs(alpha(k)))) {
      ++k;
      break;
    }
    beta(k) = b;
    v[k + 1] = y / b;
    mv[k + 1] = x / b;
  }
  MatX t = MatX::Zero(k, k);
  for (int i = 0; i < k; ++i) {
    t(i, i) = alpha(i);
    if (i + 1 < k) t(i, i + 1) = t(i + 1, i) = beta(i);
  }
  return std::max(
      0.0, Eigen::SelfAdjointEigenSolver<MatX>(t, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff());
}

}  // namespace

StabilityEstimate EstimateStability(const Model& model, const State& state) {
  StretchScratch scratch;
  scratch.Resize(model.num_points());
  ForceJacobians jac;
  jac.Resize(model.num_points());
  Points f(model.num_points(), 3);
  ComputeForces(model, state.q, state.qd, {}, &scratch, &f, nullptr, &jac);

  StabilityEstimate e;
  e.omega_max = std::sqrt(LargestEigenvalue(model, jac.stiffness, jac.rank1_u, jac.rank1_coeff));
  e.damping_max = LargestEigenvalue(model, jac.damping, jac.rank1_u, 0.0);
  const double half = 0.5 * e.damping_max;
  e.rate_max = half + std::sqrt(half * half + e.omega_max * e.omega_max);
  e.h_times_rate = model.substep_size() * e.rate_max;
  e.stable_substeps =
      std::max(1, static_cast<int>(std::ceil(e.rate_max * model.step_size() / kRk4StabilityLimit)));
  return e;
}

}  // namespace viscera::mechanics
