#pragma once
/// Cholesky factor of a symmetric positive definite BlockBand matrix (3x3 blocks, block
/// half-bandwidth 3): the implicit integrator's M + h D + h^2 K while no contact couples distant
/// parts of the chain. Fixed-size 3x3 block arithmetic, O(n), no allocation after the first
/// factorization. CHOLMOD (cholmod_solver.h) handles general patterns.
#include <vector>

#include "mechanics/block_band.h"

namespace viscera::mechanics {

class BlockBandCholesky {
 public:
  /// Factors A = L L^T. Returns false when A is not positive definite.
  bool Factor(const BlockBand& a);

  /// Solves A x = b in place; b holds 3n values ordered x0 y0 z0 x1 ...
  /// `first`: b's rows of the blocks before it are +0 (a sparse right-hand side); the forward
  /// pass, which would leave them +0, starts there, with the same numbers as from block 0.
  void SolveInPlace(double* b, int first = 0) const;
  /// Solves A x = a and A x = b in place in one pass (each column's numbers exactly
  /// SolveInPlace's; the factor is read once for both); `first` as SolveInPlace's, for both.
  /// @pre a and b do not overlap.
  void SolveTwoInPlace(double* a, double* b, int first = 0) const;
  /// The same for four right-hand sides in one pass (the lanes of one AVX register in the AVX
  /// clone), each column's numbers exactly SolveInPlace's; `first` for all four.
  /// @pre a, b, c and d do not overlap.
  void SolveFourInPlace(double* a, double* b, double* c, double* d, int first = 0) const;

  /// The factor's blocks (tests): L(i, i - d), d = 0 .. 3, and L(i, i)^-1 (lower triangular).
  int n() const { return n_; }
  const Mat3& lower_block(int i, int d) const { return L(i, d); }
  const Mat3& inverse_diagonal(int i) const { return inv_diag_[i]; }

 private:
  // l_[i * 4 + d] = L(i, i - d); inv_diag_[i] = L(i, i)^-1 (lower triangular).
  std::vector<Mat3> l_;
  std::vector<Mat3> inv_diag_;
  int n_ = 0;
  template <class T, class Rows>
  void Solve(const Rows& rows, int first) const;
  const Mat3& L(int i, int d) const { return l_[static_cast<size_t>(i) * BlockBand::kWidth + d]; }
  Mat3& L(int i, int d) { return l_[static_cast<size_t>(i) * BlockBand::kWidth + d]; }
};

}  // namespace viscera::mechanics
