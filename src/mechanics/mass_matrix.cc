#include "mechanics/mass_matrix.h"

#include "spline/gauss_legendre.h"

namespace viscera::mechanics {

Band BuildMassBand(const spline::CatmullRom& curve, double mass) {
  using Rule = spline::GaussLegendre<4>;
  const int n = curve.num_points();
  const double segment_mass = mass / curve.num_segments();
  Band band = Band::Zero(n, kHalfBand + 1);
  for (int j = 0; j < curve.num_segments(); ++j) {
    // Gram block of the segment's window: G(a, b) = integral B_a(u) B_b(u) du.
    Eigen::Matrix4d gram = Eigen::Matrix4d::Zero();
    for (int g = 0; g < 4; ++g) {
      const spline::SegmentBasis b = curve.Basis(j, Rule::kNodes[g]);
      const Eigen::Vector4d w(b.w[0], b.w[1], b.w[2], b.w[3]);
      gram += Rule::kWeights[g] * w * w.transpose();
    }
    const int f = curve.FirstIndex(j);
    for (int a = 0; a < 4; ++a) {
      for (int b = a; b < 4; ++b) band(f + a, b - a) += segment_mass * gram(a, b);
    }
  }
  return band;
}

VecX MassRowSums(const Band& band) {
  const int n = static_cast<int>(band.rows());
  VecX sums = VecX::Zero(n);
  for (int i = 0; i < n; ++i) {
    sums(i) += band(i, 0);
    for (int d = 1; d <= kHalfBand && i + d < n; ++d) {
      sums(i) += band(i, d);
      sums(i + d) += band(i, d);
    }
  }
  return sums;
}

}  // namespace viscera::mechanics
