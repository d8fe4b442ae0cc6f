#pragma once
/// Classical explicit Runge-Kutta 4 (the paper's integrator, France et al. 2005, section 3.4).
/// Stable while h * omega_max < ~2.8 (see stability.h): stiff springs need sub-steps.
#include "mechanics/integrator.h"
#include "mechanics/mass_solver.h"

namespace viscera::mechanics {

class Rk4Integrator final : public Integrator {
 public:
  explicit Rk4Integrator(const Model& model, Interactions* interactions = nullptr);
  void Advance(std::span<const PointLoad> loads, double h, State* state) override;

 private:
  // a <- constrained acceleration at (q, qd).
  void Acceleration(std::span<const PointLoad> loads, const Points& q, const Points& qd, Points* a);

  const Model& model_;
  Interactions* interactions_;
  MassSolver mass_solver_;
  StretchScratch scratch_;
  Points q_stage_, v_stage_;
  Points k1v_, k2v_, k3v_, k4v_;
  Points k2q_, k3q_, k4q_;
};

}  // namespace viscera::mechanics
