#pragma once
/// Accelerations from generalized forces: A = M^-1 B, projected onto the pins' constraints
/// G A = 0 (G: the pinned curve points' basis rows). The pins are solved inside the system
/// (Schur complement: A = A0 - Y (G Y)^-1 G A0, Y = M^-1 G^T), so they do no work; they are
/// never accelerations zeroed after the fact. RK4 and implicit Euler preserve G q exactly
/// because the constraint is linear and constant.
#include <memory>

#include "mechanics/cholmod_solver.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

class MassSolver {
 public:
  /// Uses the model's banded factor, or factors M with CHOLMOD (params().mass_solver).
  explicit MassSolver(const Model& model);

  /// b <- M^-1 b (#N by 3). Allocates nothing.
  void SolveInPlace(Points* b);

  /// b <- the constrained acceleration for generalized forces b. Allocates nothing.
  void SolveConstrainedInPlace(Points* b);

 private:
  const Model& model_;
  std::unique_ptr<CholmodBandSolver> cholmod_;
  MatX pin_residual_, pin_lambda_;  // #pins by 3
};

}  // namespace viscera::mechanics
