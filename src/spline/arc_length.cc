#include "spline/arc_length.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"
#include "spline/gauss_legendre.h"

namespace viscera::spline {

void ArcLengthTable::Build(const CatmullRom& curve, const Points& q) {
  using Rule = GaussLegendre<3>;
  const int k = samples_per_segment_;
  const int n = curve.num_segments();
  cumulative_.resize(static_cast<size_t>(n) * k + 1);
  cumulative_[0] = 0.0;
  size_t i = 0;
  for (int j = 0; j < n; ++j) {
    const Eigen::Matrix<double, 4, 3> poly =
        curve.Coefficients(j).transpose() * q.middleRows<4>(curve.FirstIndex(j));
    for (int sub = 0; sub < k; ++sub) {
      double piece = 0.0;
      for (int g = 0; g < 3; ++g) {
        const double u = (sub + Rule::kNodes[g]) / k;
        const Eigen::RowVector3d d =
            poly.row(1) + 2.0 * u * poly.row(2) + 3.0 * u * u * poly.row(3);
        piece += Rule::kWeights[g] * d.norm();
      }
      cumulative_[i + 1] = cumulative_[i] + piece / k;
      ++i;
    }
  }
}

double ArcLengthTable::ArcLengthAt(double s) const {
  VISCERA_ASSERT(!cumulative_.empty());
  const double x = std::clamp(s, 0.0, 1.0) * (cumulative_.size() - 1);
  const size_t i = std::min(static_cast<size_t>(x), cumulative_.size() - 2);
  const double f = x - i;
  return cumulative_[i] + f * (cumulative_[i + 1] - cumulative_[i]);
}

double ArcLengthTable::ParameterAt(double arc) const {
  size_t interval = 0;
  return ParameterAt(arc, &interval);
}

double ArcLengthTable::ParameterAt(double arc, size_t* interval) const {
  VISCERA_ASSERT(!cumulative_.empty());
  const size_t last = cumulative_.size() - 1;
  if (arc <= 0.0) return 0.0;
  if (arc >= cumulative_[last]) return 1.0;
  // The last interval whose start is at or before arc. A sweep in increasing arc walks a few
  // entries from the last one; elsewhere, a binary search.
  size_t i = std::min(*interval, last - 1);
  if (cumulative_[i] <= arc) {
    for (int walked = 0; walked < 8 && cumulative_[i + 1] <= arc; ++walked)
      ++i;  // arc < cumulative_[last]
  }
  if (!(cumulative_[i] <= arc && arc < cumulative_[i + 1])) {
    i = std::upper_bound(cumulative_.begin(), cumulative_.end(), arc) - cumulative_.begin() - 1;
  }
  *interval = i;
  const double span = cumulative_[i + 1] - cumulative_[i];
  const double f = span > 0.0 ? (arc - cumulative_[i]) / span : 0.0;
  return (i + f) / last;
}

}  // namespace viscera::spline
