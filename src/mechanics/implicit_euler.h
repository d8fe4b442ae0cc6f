#pragma once
/// Linearly implicit (semi-implicit backward) Euler, as in Baraff & Witkin 1998:
///   (M + h D + h^2 K) dv = h (F(q, v) - h K v),   v' = v + dv,   q' = q + h v',
/// with K = -dF/dq, D = -dF/dv and M the mass matrix acting on each axis. The 3N unknowns are
/// ordered x0 y0 z0 x1 ...; the matrix is block banded (|i - j| <= 3) and is factored either by
/// a 3x3 block-band Cholesky or by CHOLMOD, whose symbolic analysis is done once and reused
/// while the pattern holds (params().linear_solver; the faster is the default). The global
/// stretching energy's dense rank-one stiffness is applied by Sherman-Morrison, and the pins are
/// solved inside the system (Schur complement), all from one multi-column CHOLMOD solve.
/// Unconditionally stable for the linearized system; it damps high frequencies (first order).
#include <vector>

#include "mechanics/block_band_cholesky.h"
#include "mechanics/cholmod_solver.h"
#include "mechanics/integrator.h"

namespace viscera::mechanics {

class ImplicitEulerIntegrator final : public Integrator {
 public:
  explicit ImplicitEulerIntegrator(const Model& model, Interactions* interactions = nullptr);
  void Advance(std::span<const PointLoad> loads, double h, State* state) override;

  /// Steps whose matrix CHOLMOD found not positive definite (the step then falls back to a
  /// damped explicit update). Should stay 0.
  int64_t factorization_failures() const { return factorization_failures_; }

 private:
  void BuildPattern();
  void AssembleSystem(double h);   // system_ = M + h D + h^2 K
  bool FactorSystem();
  void SolveColumns();             // rhs_ <- system_^-1 rhs_

  const Model& model_;
  Interactions* interactions_;
  int n_;                        // control points
  int num_pins_;
  bool use_cholmod_;
  BlockBand system_;
  BlockBandCholesky band_factor_;
  CholmodCommon common_;
  CholmodSolver solver_;
  CholmodSolveWorkspace solve_work_;
  std::vector<int> slot_;        // (block i, d, alpha, beta) -> index in the CSC values, or -1
  StretchScratch scratch_;
  ForceJacobians jac_;
  Points force_, kv_;
  MatX rhs_;                     // 3N by (2 + 3 #pins): [r, u, G^T columns], solved in place
  MatX schur_;                   // 3 #pins square
  Eigen::LDLT<MatX> schur_ldlt_;
  VecX pin_rhs_, pin_lambda_;
  int64_t factorization_failures_ = 0;
};

}  // namespace viscera::mechanics
