#include "mechanics/block_band.h"

#include "mechanics/avx_clone.h"

namespace viscera::mechanics {

VISCERA_AVX_CLONE void BlockBand::Multiply(const double* x_data, double* y_data) const {
  const Eigen::Map<const Points> x(x_data, n_, 3);
  Eigen::Map<Points> y(y_data, n_, 3);
  // Row by row, each row's terms summed from zero in the order of a pass over the upper
  // blocks that scatters both halves (A(i - d, i)^T x_(i-d) for d = 3, 2, 1, then A(i, i + d)
  // x_(i+d) for d = 0 .. 3): the same numbers, one store per row instead of seven updates.
  for (int i = 0; i < n_; ++i) {
    Vec3 sum = Vec3::Zero();
    for (int d = std::min(i, kWidth - 1); d >= 1; --d)
      sum += block(i - d, d).transpose() * x.row(i - d).transpose();
    for (int d = 0; d < kWidth && i + d < n_; ++d) sum += block(i, d) * x.row(i + d).transpose();
    y.row(i) = sum.transpose();
  }
}

}  // namespace viscera::mechanics
