#include "spline/arc_length.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace viscera::spline {
namespace {

// 4-point Gauss-Lobatto on [0, 1] (exact to degree 5): its end nodes are the table's entries.
constexpr double kLobatto[4] = {0.0, 0.27639320225002103, 0.72360679774997897, 1.0};  // (1 -+ 1/sqrt 5) / 2
constexpr double kLobattoEnd = 1.0 / 12.0, kLobattoMid = 5.0 / 12.0;
// Integrals from 0 to t of the cubic Lagrange basis on those nodes, as powers t^(p+1) (row p)
// of each node's value (column): the speed's cubic interpolant integrated. At t = 1 the
// columns sum to the Lobatto weights.
constexpr double kIntegratedLagrange[4][4] = {
    {1.0, 0.0, 0.0, 0.0},
    {-3.0, 4.045084971874738, -1.5450849718747377, 0.5},
    {3.3333333333333335, -6.423503277082808, 4.7568366104161415, -1.6666666666666667},
    {-1.25, 2.7950849718747377, -2.7950849718747377, 1.25}};

}  // namespace

void ArcLengthTable::Build(const CatmullRom& curve, const Points& q) {
  const int k = samples_per_segment_;
  const double step = 1.0 / k;  // of u per interval
  const double inner[2] = {kLobatto[1] * step, kLobatto[2] * step};
  const int n = curve.num_segments();
  const size_t intervals = static_cast<size_t>(n) * k;
  cumulative_.resize(intervals + 1);
  poly_.resize(intervals);
  cumulative_[0] = 0.0;
  size_t i = 0;
  for (int j = 0; j < n; ++j) {
    const Eigen::Matrix<double, 4, 3> poly =
        curve.Coefficients(j).transpose() * q.middleRows<4>(curve.FirstIndex(j));
    // dP/du = d0 + u d1 + u^2 d2.
    const Eigen::RowVector3d d0 = poly.row(1), d1 = 2.0 * poly.row(2), d2 = 3.0 * poly.row(3);
    const auto speed = [&](double u) { return (d0 + u * (d1 + u * d2)).norm(); };
    // The speed is continuous across segments (the curve is C1): each segment computes its
    // start once and shares each interval's end with the next interval.
    double start = d0.norm();
    for (int sub = 0; sub < k; ++sub) {
      const double u0 = sub * step;
      const double s[4] = {start, speed(u0 + inner[0]), speed(u0 + inner[1]), speed((sub + 1) * step)};
      // In the interval's own parameter t = (u - u0) k, d(arc)/dt = |dP/du| / k.
      std::array<double, 4>& c = poly_[i];
      for (int p = 0; p < 4; ++p) {
        c[p] = step * (kIntegratedLagrange[p][0] * s[0] + kIntegratedLagrange[p][1] * s[1] +
                       kIntegratedLagrange[p][2] * s[2] + kIntegratedLagrange[p][3] * s[3]);
      }
      cumulative_[i + 1] = cumulative_[i] + step * (kLobattoEnd * (s[0] + s[3]) + kLobattoMid * (s[1] + s[2]));
      start = s[3];
      ++i;
    }
  }
}

double ArcLengthTable::Interpolate(size_t i, double t) const {
  const std::array<double, 4>& c = poly_[i];
  return cumulative_[i] + t * (c[0] + t * (c[1] + t * (c[2] + t * c[3])));
}

double ArcLengthTable::ArcLengthAt(double s) const {
  VISCERA_ASSERT(!cumulative_.empty());
  const double x = std::clamp(s, 0.0, 1.0) * (cumulative_.size() - 1);
  const size_t i = std::min(static_cast<size_t>(x), cumulative_.size() - 2);
  return Interpolate(i, x - i);
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
  // The interval holding arc: cumulative_[i] <= arc < cumulative_[i + 1]. A sweep in increasing
  // arc walks a few steps from the last one; elsewhere, a binary search.
  size_t i = std::min(*interval, last - 1);
  if (cumulative_[i] <= arc) {
    for (int walked = 0; walked < 4 && arc >= cumulative_[i + 1]; ++walked) ++i;  // arc < cumulative_[last]
  }
  if (!(cumulative_[i] <= arc && arc < cumulative_[i + 1])) {
    i = std::upper_bound(cumulative_.begin(), cumulative_.end(), arc) - cumulative_.begin() - 1;
  }
  *interval = i;
  const double span = cumulative_[i + 1] - cumulative_[i];
  if (!(span > 0.0)) return static_cast<double>(i) / last;
  // The inverse's cubic Hermite interpolant (its end slopes 1 / speed, limited to 3 times the
  // mean so that it is monotone: Fritsch and Carlson 1980) is within a few percent of an interval
  // of the quartic's inverse, then one Newton step on the quartic squares that error. A fixed
  // count of operations: continuous in arc and in q.
  const std::array<double, 4>& c = poly_[i];
  const double end_speed = c[0] + 2.0 * c[1] + 3.0 * c[2] + 4.0 * c[3];  // d(arc)/dt at t = 1
  const double g0 = c[0] > span / 3.0 ? span / c[0] : 3.0;
  const double g1 = end_speed > span / 3.0 ? span / end_speed : 3.0;
  const double z = (arc - cumulative_[i]) / span, z2 = z * z, z3 = z2 * z;
  double t = (3.0 * z2 - 2.0 * z3) + (z3 - 2.0 * z2 + z) * g0 + (z3 - z2) * g1;
  const double slope = c[0] + t * (2.0 * c[1] + t * (3.0 * c[2] + t * 4.0 * c[3]));
  if (slope > 0.0) t -= (Interpolate(i, t) - arc) / slope;
  t = std::clamp(t, 0.0, 1.0);
  return (i + t) / last;
}

}  // namespace viscera::spline
