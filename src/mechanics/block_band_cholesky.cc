#include "mechanics/block_band_cholesky.h"

#include "mechanics/avx_clone.h"

#include <algorithm>
#include <cmath>

namespace viscera::mechanics {
namespace {

constexpr int kBand = BlockBand::kWidth - 1;  // 3 blocks below the diagonal

// Lower Cholesky factor of a 3x3 SPD block and its inverse; false if not PD.
[[gnu::always_inline]] inline bool Chol3(const Mat3& s, Mat3* inv) {
  const double l00sq = s(0, 0);
  if (!(l00sq > 0.0)) return false;
  const double l00 = std::sqrt(l00sq);
  const double l10 = s(1, 0) / l00, l20 = s(2, 0) / l00;
  const double l11sq = s(1, 1) - l10 * l10;
  if (!(l11sq > 0.0)) return false;
  const double l11 = std::sqrt(l11sq);
  const double l21 = (s(2, 1) - l20 * l10) / l11;
  const double l22sq = s(2, 2) - l20 * l20 - l21 * l21;
  if (!(l22sq > 0.0)) return false;
  const double l22 = std::sqrt(l22sq);
  // Inverse of the lower triangle [l00 0 0; l10 l11 0; l20 l21 l22].
  const double i00 = 1.0 / l00, i11 = 1.0 / l11, i22 = 1.0 / l22;
  const double i10 = -l10 * i00 * i11;
  const double i21 = -l21 * i11 * i22;
  const double i20 = -(l20 * i00 + l21 * i10) * i22;
  *inv << i00, 0.0, 0.0, i10, i11, 0.0, i20, i21, i22;
  return true;
}

// A(i, j) for i >= j from the upper block storage.
Mat3 Lower(const BlockBand& a, int i, int j) { return a.block(j, i - j).transpose(); }

}  // namespace

VISCERA_AVX_CLONE bool BlockBandCholesky::Factor(const BlockBand& a) {
  n_ = a.n();
  l_.resize(static_cast<size_t>(n_) * BlockBand::kWidth);
  inv_diag_.resize(n_);
  for (int j = 0; j < n_; ++j) {
    // Diagonal: S = A(j,j) - sum_k L(j,k) L(j,k)^T, L(j,j) = chol(S).
    Mat3 s = a.block(j, 0);
    for (int d = 1; d <= std::min(j, kBand); ++d) s.noalias() -= L(j, d) * L(j, d).transpose();
    if (!Chol3(s, &inv_diag_[j])) return false;
    // Below: L(i,j) = (A(i,j) - sum_k L(i,k) L(j,k)^T) L(j,j)^-T for k < j within both bands.
    for (int i = j + 1; i <= std::min(n_ - 1, j + kBand); ++i) {
      Mat3 b = Lower(a, i, j);
      for (int k = std::max(0, i - kBand); k < j; ++k) b.noalias() -= L(i, i - k) * L(j, j - k).transpose();
      L(i, i - j).noalias() = b * inv_diag_[j].transpose();
    }
  }
  return true;
}

template <int kColumns>
void BlockBandCholesky::Solve(const std::array<double*, kColumns>& columns) const {
  using Vec = Eigen::Map<Vec3>;
  // Forward: L y = b.
  for (int i = 0; i < n_; ++i) {
    for (double* b : columns) {
      Vec3 v = Vec(b + 3 * i);
      for (int d = 1; d <= std::min(i, kBand); ++d) v.noalias() -= L(i, d) * Vec(b + 3 * (i - d));
      Vec(b + 3 * i).noalias() = inv_diag_[i] * v;
    }
  }
  // Backward: L^T x = y.
  for (int i = n_ - 1; i >= 0; --i) {
    for (double* b : columns) {
      Vec3 v = Vec(b + 3 * i);
      for (int d = 1; d <= std::min(n_ - 1 - i, kBand); ++d) v.noalias() -= L(i + d, d).transpose() * Vec(b + 3 * (i + d));
      Vec(b + 3 * i).noalias() = inv_diag_[i].transpose() * v;
    }
  }
}

template void BlockBandCholesky::Solve<1>(const std::array<double*, 1>&) const;
template void BlockBandCholesky::Solve<2>(const std::array<double*, 2>&) const;

}  // namespace viscera::mechanics
