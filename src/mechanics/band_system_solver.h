#pragma once
/// The implicit step's band system P = M + ĥ D + ĥ² K (3N unknowns ordered x0 y0 z0 x1 ...,
/// 3x3 blocks within |i - j| <= 3), assembled, factored and solved for one or many right-hand
/// sides. It is factored either by the 3x3 block-band Cholesky or by CHOLMOD, whose symbolic
/// analysis is done once for the band's fixed pattern (ModelParams::linear_solver; the faster is
/// the default). Kept apart from ImplicitEulerIntegrator so that the step's algebra (rank-one
/// term, pins, tips, CG, impacts) reads one small interface whichever factorization is chosen,
/// and so that the two solvers' workspaces live in one place, preallocated: a solve allocates
/// nothing once the first one has sized CHOLMOD's workspaces.
#include <span>
#include <vector>

#include "mechanics/banded_cholesky.h"
#include "mechanics/block_band.h"
#include "mechanics/block_band_cholesky.h"
#include "mechanics/cholmod_solver.h"
#include "mechanics/forces.h"

namespace viscera::mechanics {

class BandSystemSolver {
 public:
  BandSystemSolver(int num_points, bool use_cholmod);

  /// P = M + damping_weight D + stiffness_weight K, M the mass band acting on each axis.
  void Assemble(const Band& mass, const ForceJacobians& jacobians, double damping_weight,
                double stiffness_weight);
  /// Factors P; false if it is not positive definite.
  bool Factor();
  /// x <- P^-1 x (3N values); x is +0 in the rows of the points before `first` (a sparse
  /// right-hand side), which the band factor's forward pass then skips (the same numbers).
  void SolveInPlace(double* x, int first = 0);
  /// a <- P^-1 a and b <- P^-1 b, each with SolveInPlace's numbers, `first` for both.
  void SolveTwoInPlace(double* a, double* b, int first = 0);
  /// Columns 0 and `from`.. of rhs (3N rows, `from` >= 1), and the columns `extra` (3N values
  /// each, +0 in the rows of the points before extra_first's), <- P^-1 of each; the columns of
  /// rhs between are left as they are. The band factor takes them four at a time (each column's
  /// numbers those of a one-column solve), CHOLMOD column 0 alone, the rest of rhs in one call
  /// and each extra column alone.
  void SolveColumns(MatX* rhs, Eigen::Index from, std::span<double* const> extra = {},
                    std::span<const int> extra_first = {});
  /// The last assembled P (its products: BlockBand::Multiply).
  const BlockBand& system() const { return system_; }

 private:
  void BuildPattern();

  int n_;  // control points
  bool use_cholmod_;
  BlockBand system_;
  BlockBandCholesky band_factor_;
  CholmodCommon common_;
  CholmodSolver solver_;
  CholmodSolveWorkspace solve_work_;      // the multi-column solve of SolveColumns
  CholmodSolveWorkspace solve_one_work_;  // one vector: its own, so neither reallocates
  VecX spare_;             // the fourth lane's column when SolveColumns has three left
  std::vector<int> slot_;  // (block i, d, alpha, beta) -> index in the CSC values, or -1
};

}  // namespace viscera::mechanics
