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

double Speed(const Eigen::Matrix<double, 4, 3>& poly, double u) {
  return (poly.row(1) + 2.0 * u * poly.row(2) + 3.0 * u * u * poly.row(3)).norm();
}

}  // namespace

void ArcLengthTable::Build(const CatmullRom& curve, const Points& q) {
  const int k = samples_per_segment_;
  const int n = curve.num_segments();
  const size_t intervals = static_cast<size_t>(n) * k;
  cumulative_.resize(intervals + 1);
  poly_.resize(intervals);
  cumulative_[0] = 0.0;
  size_t i = 0;
  for (int j = 0; j < n; ++j) {
    const Eigen::Matrix<double, 4, 3> poly =
        curve.Coefficients(j).transpose() * q.middleRows<4>(curve.FirstIndex(j));
    // The speed is continuous across segments (the curve is C1): each segment computes its
    // start once and shares each interval's end with the next interval.
    double start = Speed(poly, 0.0) / k;  // d(arc)/dt, t the interval's parameter
    for (int sub = 0; sub < k; ++sub) {
      const double speed[4] = {start, Speed(poly, (sub + kLobatto[1]) / k) / k,
                               Speed(poly, (sub + kLobatto[2]) / k) / k, Speed(poly, (sub + 1.0) / k) / k};
      std::array<double, 4>& c = poly_[i];
      for (int p = 0; p < 4; ++p) {
        c[p] = 0.0;
        for (int g = 0; g < 4; ++g) c[p] += kIntegratedLagrange[p][g] * speed[g];
      }
      cumulative_[i + 1] = cumulative_[i] + kLobattoEnd * (speed[0] + speed[3]) + kLobattoMid * (speed[1] + speed[2]);
      start = speed[3];
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
  // arc walks a step or two from the last one; elsewhere, a binary search.
  size_t i = std::min(*interval, last - 1);
  if (cumulative_[i] <= arc && arc < cumulative_[i + 1]) {
    // the hint itself
  } else if (i + 2 <= last && cumulative_[i + 1] <= arc && arc < cumulative_[i + 2]) {
    ++i;
  } else {
    i = std::upper_bound(cumulative_.begin(), cumulative_.end(), arc) - cumulative_.begin() - 1;
  }
  *interval = i;
  const double span = cumulative_[i + 1] - cumulative_[i];
  if (!(span > 0.0)) return static_cast<double>(i) / last;
  // Newton on the interval's quartic from the straight line's answer, kept inside a shrinking
  // bracket (bisection when a step would leave it). It converges quadratically: once a step is
  // below 1e-9 the next would be below rounding, so it stops there.
  double lo = 0.0, hi = 1.0;
  double t = std::clamp((arc - cumulative_[i]) / span, 0.0, 1.0);
  const std::array<double, 4>& c = poly_[i];
  for (int iter = 0; iter < 50; ++iter) {
    const double r = Interpolate(i, t) - arc;
    if (r == 0.0) break;
    if (r > 0.0) {
      hi = t;
    } else {
      lo = t;
    }
    const double slope = c[0] + t * (2.0 * c[1] + t * (3.0 * c[2] + t * 4.0 * c[3]));
    const double next = slope > 0.0 ? t - r / slope : -1.0;
    if (!(next > lo && next < hi)) {
      t = 0.5 * (lo + hi);  // bisection
      continue;
    }
    const bool converged = std::abs(next - t) <= 1e-9;
    t = next;
    if (converged) break;
  }
  return (i + t) / last;
}

}  // namespace viscera::spline
