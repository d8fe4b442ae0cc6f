#include "mechanics/rk4.h"

namespace viscera::mechanics {

Rk4Integrator::Rk4Integrator(const Model& model, Interactions* interactions)
    : model_(model), interactions_(interactions), mass_solver_(model) {
  const int n = model.num_points();
  scratch_.Resize(n);
  for (Points* p : {&q_stage_, &v_stage_, &k1v_, &k2v_, &k3v_, &k4v_, &k2q_, &k3q_, &k4q_})
    p->setZero(n, 3);
}

void Rk4Integrator::Acceleration(std::span<const PointLoad> loads, const Points& q,
                                 const Points& qd, Points* a) {
  ComputeForces(model_, q, qd, loads, &scratch_, a, nullptr, nullptr, interactions_);
  mass_solver_.SolveConstrainedInPlace(a);
}

void Rk4Integrator::Advance(std::span<const PointLoad> loads, double h, State* state) {
  Points& q = state->q;
  Points& v = state->qd;
  // Stage 1: k1 = (v, a(q, v)).
  Acceleration(loads, q, v, &k1v_);
  // Stage 2 at the midpoint along k1.
  q_stage_ = q + (0.5 * h) * v;
  k2q_ = v + (0.5 * h) * k1v_;
  Acceleration(loads, q_stage_, k2q_, &k2v_);
  // Stage 3 at the midpoint along k2.
  q_stage_ = q + (0.5 * h) * k2q_;
  k3q_ = v + (0.5 * h) * k2v_;
  Acceleration(loads, q_stage_, k3q_, &k3v_);
  // Stage 4 at the end along k3.
  q_stage_ = q + h * k3q_;
  k4q_ = v + h * k3v_;
  Acceleration(loads, q_stage_, k4q_, &k4v_);

  q += (h / 6.0) * (v + 2.0 * k2q_ + 2.0 * k3q_ + k4q_);
  v += (h / 6.0) * (k1v_ + 2.0 * k2v_ + 2.0 * k3v_ + k4v_);
}

}  // namespace viscera::mechanics
