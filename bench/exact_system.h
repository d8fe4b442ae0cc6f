#pragma once
// The implicit step's exact matrix as a sparse matrix, for direct solvers (bench_direct_coupling
// and tests/mechanics/direct_coupling_test.cc; docs/self-coupling.md).
//
// After ImplicitEulerIntegrator::Advance the integrator keeps its band system P (each self pair
// as 2 H per side; read through mechanics::ImplicitSystemView) and Interactions keeps the pairs'
// common modes weighed with (h^2, h). The exact matrix is A = A_s + w u u^T with A_s = P minus the
// common modes: A_s is sparse (the band plus a 4 x 4 block of points between each pair's two
// windows), the rank-one term is dense and is applied by Sherman-Morrison, as the step does. A_s is
// read column by column: the band's entries, plus AddCommonModeTerms applied to unit vectors (so it
// holds whatever the step's products hold, with no second copy of the pairs' algebra).
#include <cholmod.h>

#include <utility>
#include <vector>

#include "common/types.h"
#include "mechanics/block_band.h"
#include "mechanics/block_band_cholesky.h"
#include "mechanics/cholmod_solver.h"
#include "mechanics/implicit_system_view.h"
#include "mechanics/interactions.h"

namespace viscera::bench {

/// Upper triangle of a symmetric matrix in compressed columns, rows sorted (CHOLMOD's input).
struct SparseUpper {
  int n = 0;
  std::vector<int> col_ptr, row;
  std::vector<double> value;
  int64_t nonzeros() const { return static_cast<int64_t>(row.size()); }
};

/// The last sub-step's A_s (the exact matrix without its rank-one term). Entries of the band
/// are all kept (its structure); the pairs' entries outside it where nonzero.
/// @pre the model has no pins (a direct solve would need their Schur complement: not built).
SparseUpper AssembleExact(const mechanics::ImplicitSystemView& system,
                          const mechanics::Interactions& interactions);

/// The pairs' part of the pattern: point pairs (i, j), j - i > 3, with an entry in A_s.
std::vector<std::pair<int, int>> CoupledBlocks(const SparseUpper& a);

/// y = (A_s + w u u^T) x, from the upper triangle.
void MultiplySymmetric(const SparseUpper& a, double w, const VecX& u, const VecX& x, VecX* y);

enum class Ordering { kNatural, kAmd, kMetis, kNesdis };
const char* OrderingName(Ordering ordering);

/// CHOLMOD's LL' of one pattern with a chosen ordering, simplicial or supernodal.
class DirectSolver {
 public:
  DirectSolver(mechanics::CholmodCommon* common, Ordering ordering, bool supernodal);
  ~DirectSolver();
  DirectSolver(const DirectSolver&) = delete;
  DirectSolver& operator=(const DirectSolver&) = delete;

  /// Symbolic analysis of a's pattern (ordering, elimination tree, column counts).
  void Analyze(const SparseUpper& a);
  /// Numeric factorization of a, whose pattern Analyze saw. False if not positive definite.
  bool Factorize(const SparseUpper& a);
  /// x <- A_s^-1 x.
  void Solve(VecX* x);
  /// x <- (A_s + w u u^T)^-1 x by Sherman-Morrison (z: scratch, A_s^-1 u on return).
  void SolveWithRankOne(double w, const VecX& u, VecX* x, VecX* z);
  /// Nonzeros of L and the factorization's flops, from the last Analyze.
  double factor_nonzeros() const { return lnz_; }
  double factor_flops() const { return flops_; }
  bool supernodal() const { return supernodal_; }

 private:
  cholmod_common* common_;
  Ordering ordering_;
  bool supernodal_;
  cholmod_sparse* a_ = nullptr;
  cholmod_factor* factor_ = nullptr;
  cholmod_dense *x_ = nullptr, *y_ = nullptr, *e_ = nullptr;
  double lnz_ = 0.0, flops_ = 0.0;
};

/// x <- M^-1 x for a symmetric positive definite M that approximates the exact matrix.
class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  virtual void Apply(VecX* x) const = 0;
};

/// The step's preconditioner without pins: the band factor of P, then w u u^T by Sherman-Morrison.
class BandPreconditioner final : public Preconditioner {
 public:
  explicit BandPreconditioner(const mechanics::ImplicitSystemView& system);
  void Apply(VecX* x) const override;  // x <- (P + w u u^T)^-1 x

 private:
  mechanics::BlockBandCholesky factor_;
  double w_;
  VecX u_, z_;
  double denominator_;
};

/// The step's preconditioned CG (mechanics::PreconditionedCg) on the integrator's own exact
/// product (MultiplyExact), with another preconditioner: from *x with *r = b - A *x, until r^T M^-1
/// r falls to max(stop, relative^2 times its start) or after max_iterations (or when p^T A p is not
/// positive). Updates x and r; returns the iterations.
int ContinueCg(const mechanics::ImplicitSystemView& system, const Preconditioner& preconditioner,
               double stop, double relative, int max_iterations, VecX* x, VecX* r);

/// ContinueCg from x = 0, until the preconditioned residual is `tolerance` of b's (in that norm).
int SolveByCg(const mechanics::ImplicitSystemView& system, const Preconditioner& preconditioner,
              const VecX& b, double tolerance, int max_iterations, VecX* x);

/// The start of the last sub-step's CG: the band's answer plus the correction extrapolated from
/// the two sub-steps before, `extrapolated` (read from the state after the sub-step before:
/// 2 State::cg_correction - State::cg_previous_correction).
VecX CgWarmStart(const BandPreconditioner& band, const VecX& b, const VecX& extrapolated);

}  // namespace viscera::bench
