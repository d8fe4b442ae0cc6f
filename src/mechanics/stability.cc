#include "mechanics/stability.h"

#include <cmath>

#include "mechanics/forces.h"
#include "mechanics/mass_solver.h"

namespace viscera::mechanics {
namespace {

// Largest eigenvalue of M^-1 A for a symmetric PSD A (rank-one part c u u^T added), by power
// iteration from a fixed, non-smooth start vector (reaches high-frequency modes fast).
double LargestEigenvalue(const Model& model, const BlockBand& a, const Points& u, double c) {
  const int n = model.num_points();
  MassSolver mass(model);
  Points x(n, 3), y(n, 3);
  for (int i = 0; i < n; ++i) x.row(i) << (i % 2 ? 1.0 : -1.0), (i % 3 ? 0.7 : -0.4), (i % 5 ? 0.3 : -1.1);
  x.normalize();
  double lambda = 0.0;
  for (int it = 0; it < 300; ++it) {
    a.Multiply(x, &y);
    if (c > 0.0) y += (c * (u.array() * x.array()).sum()) * u;
    mass.SolveConstrainedInPlace(&y);
    const double norm = y.norm();
    if (norm == 0.0) return 0.0;
    const double next = norm;  // x has unit norm
    x = y / norm;
    if (it > 20 && std::abs(next - lambda) <= 1e-6 * next) return next;
    lambda = next;
  }
  return lambda;
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
  e.stable_substeps = std::max(
      1, static_cast<int>(std::ceil(e.rate_max * model.step_size() / kRk4StabilityLimit)));
  return e;
}

}  // namespace viscera::mechanics
