#pragma once
/// Cholesky factor of a symmetric positive definite band matrix with half-bandwidth 3 (the
/// Catmull-Rom mass matrix: each control point influences 4 segments, so |i - j| <= 3).
/// Factor once in O(n), solve in O(n) (France et al. 2005, section 3.4).
#include <vector>

#include "common/types.h"

namespace viscera::mechanics {

inline constexpr int kHalfBand = 3;

/// Upper band of a symmetric matrix: band(i, d) = A(i, i + d), d = 0..3; entries past the
/// end are ignored. #n by 4.
using Band = Eigen::Matrix<double, Eigen::Dynamic, kHalfBand + 1, Eigen::RowMajor>;

class BandedCholesky {
 public:
  BandedCholesky() = default;

  /// Factors A = L L^T.
  /// @throws InputError when A is not positive definite.
  void Factor(const Band& band);

  int size() const { return static_cast<int>(l_.rows()); }

  /// Solves A X = B in place for the 3 columns of B (#n by 3). Allocates nothing.
  void SolveInPlace(Points* b) const;

  /// Same for one column.
  void SolveInPlace(VecX* b) const;

 private:
  // l_(i, d) = L(i, i - d); inv_diag_(i) = 1 / L(i, i).
  Band l_;
  VecX inv_diag_;
};

/// y = A x for a symmetric band matrix (upper band storage), 3 columns at once.
void BandMultiply(const Band& band, const Points& x, Points* y);

}  // namespace viscera::mechanics
