#pragma once
// Incomplete Cholesky of the exact matrix's sparse part A_s, as a CG preconditioner that sees the
// self pairs (bench_direct_coupling; docs/benchmarks.md, "Direct solvers of the coupled pairs").
//
// Eigen 3.4's IncompleteCholesky is Lin and Moré's ICT: each column of L keeps the p largest
// entries, p being the column's count in its input, and the matrix is scaled and shifted only
// where a pivot breaks down. It has no fill parameter, so `fill` extra entries per column are
// given by padding each column of the (already permuted) input with that many explicit zeros:
// they hold no value, only room for the largest fill entries (Lin-Moré's memory parameter p).
// Entries that stay zero are pruned from L before the solves. The rank-one term w u u^T is
// applied by Sherman-Morrison, as the band preconditioner does.
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include <string>

#include "exact_system.h"

namespace viscera::bench {

enum class IcOrdering { kNatural, kAmd };  // kNatural: the chain's order (the band's)

class IncompleteCholeskyPreconditioner final : public Preconditioner {
 public:
  IncompleteCholeskyPreconditioner(IcOrdering ordering, int fill);

  /// Orders A_s, factors it incompletely, and solves u for the rank-one term (u: 3N, w >= 0).
  /// Returns false if Eigen's factorization failed (ten shifts did not make it positive).
  bool Factor(const SparseUpper& a, double w, const VecX& u);
  /// x <- (L L^T + w u u^T)^-1 x, L L^T the incomplete factor in the original order.
  void Apply(VecX* x) const override;

  int64_t factor_nonzeros() const { return l_.nonZeros(); }
  /// The factorization's flops as a complete one of L's pattern would take (2 per multiply-add:
  /// sum over columns of c (c + 1), c the column's entries below the diagonal). ICT computes
  /// every update and drops afterwards, so this is a floor of its work.
  double factor_flops() const;
  std::string name() const;

 private:
  void SolveFactor(VecX* x) const;  // x <- (L L^T)^-1 x

  IcOrdering ordering_;
  int fill_;
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> permutation_;  // empty: natural
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> permuted_;                 // lower, padded
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::NaturalOrdering<int>> ict_;
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> l_;
  VecX scale_;
  double w_ = 0.0, denominator_ = 1.0;
  VecX u_, z_;
  mutable VecX scratch_;
};

/// Multiply-adds of a level-0 incomplete Cholesky of A_s in the chain's order (L holds exactly
/// A_s's pattern: only the updates that land in it are done), counted, not done; with
/// `band_only`, of the band's part alone (the band factor's own count: no fill falls outside it).
/// A floor for any IC of this pattern that sees the pairs.
double LevelZeroMultiplyAdds(const SparseUpper& a, bool band_only);

}  // namespace viscera::bench
