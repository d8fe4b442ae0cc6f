#include "mechanics/banded_cholesky.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace viscera::mechanics {

void BandedCholesky::Factor(const Band& band) {
  const int n = static_cast<int>(band.rows());
  l_.setZero(n, kHalfBand + 1);
  inv_diag_.resize(n);
  // Column-by-column Cholesky restricted to the band: L(i,j) = 0 for i - j > 3.
  for (int j = 0; j < n; ++j) {
    double diag = band(j, 0);
    for (int d = 1; d <= std::min(j, kHalfBand); ++d) diag -= l_(j, d) * l_(j, d);
    ThrowUnless(diag > 0.0, "matrix is not positive definite at row ", j, " (pivot ", diag, ")");
    l_(j, 0) = std::sqrt(diag);
    inv_diag_(j) = 1.0 / l_(j, 0);
    for (int i = j + 1; i <= std::min(n - 1, j + kHalfBand); ++i) {
      double v = band(j, i - j);  // A(i, j) = A(j, i)
      for (int k = std::max(0, i - kHalfBand); k < j; ++k) v -= l_(i, i - k) * l_(j, j - k);
      l_(i, i - j) = v * inv_diag_(j);
    }
  }
}

void BandedCholesky::SolveInPlace(Points* b) const {
  const int n = size();
  VISCERA_ASSERT(b->rows() == n);
  Points& x = *b;
  // Forward: L y = b.
  for (int i = 0; i < n; ++i) {
    Eigen::RowVector3d v = x.row(i);
    for (int d = 1; d <= std::min(i, kHalfBand); ++d) v -= l_(i, d) * x.row(i - d);
    x.row(i) = v * inv_diag_(i);
  }
  // Backward: L^T x = y.
  for (int i = n - 1; i >= 0; --i) {
    Eigen::RowVector3d v = x.row(i);
    for (int d = 1; d <= std::min(n - 1 - i, kHalfBand); ++d) v -= l_(i + d, d) * x.row(i + d);
    x.row(i) = v * inv_diag_(i);
  }
}

void BandedCholesky::SolveInPlace(VecX* b) const {
  const int n = size();
  VecX& x = *b;
  for (int i = 0; i < n; ++i) {
    double v = x(i);
    for (int d = 1; d <= std::min(i, kHalfBand); ++d) v -= l_(i, d) * x(i - d);
    x(i) = v * inv_diag_(i);
  }
  for (int i = n - 1; i >= 0; --i) {
    double v = x(i);
    for (int d = 1; d <= std::min(n - 1 - i, kHalfBand); ++d) v -= l_(i + d, d) * x(i + d);
    x(i) = v * inv_diag_(i);
  }
}

void BandMultiply(const Band& band, const Points& x, Points* y) {
  const int n = static_cast<int>(band.rows());
  y->setZero();
  for (int i = 0; i < n; ++i) {
    y->row(i) += band(i, 0) * x.row(i);
    for (int d = 1; d <= kHalfBand && i + d < n; ++d) {
      y->row(i) += band(i, d) * x.row(i + d);
      y->row(i + d) += band(i, d) * x.row(i);
    }
  }
}

}  // namespace viscera::mechanics
