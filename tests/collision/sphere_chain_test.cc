#include "collision/sphere_chain.h"

#include <gtest/gtest.h>

#include <cmath>

#include "spline/gauss_legendre.h"

namespace viscera::collision {
namespace {

constexpr double kRadius = 0.0125;  // the cavity's tube

// Arc length from s = 0 to s, integrated independently of the table: 64 pieces of 4-point
// Gauss-Legendre per segment (exact to far below the tolerances here).
double ReferenceArcLength(const spline::CatmullRom& curve, const Points& q, double s) {
  using Rule = spline::GaussLegendre<4>;
  constexpr int kPieces = 64;
  const int n = curve.num_segments();
  const double x = s * n;
  double arc = 0.0;
  for (int j = 0; j < n && j < x; ++j) {
    const double end = std::min(1.0, x - j);  // of segment j's local parameter
    for (int p = 0; p < kPieces; ++p) {
      const double a = end * p / kPieces, b = end * (p + 1) / kPieces;
      for (int g = 0; g < 4; ++g) {
        const double sg = (j + a + (b - a) * Rule::kNodes[g]) / n;
        arc += Rule::kWeights[g] * (b - a) / n * curve.Tangent(q, sg).norm();
      }
    }
  }
  return arc;
}

// A coil as tight as the cavity's pile (a loop's radius about 1.5 segments), control points
// spread unevenly along it (every other span stretched 3 to 1), wound along a wavy axis.
Points CurvedStretchedTube(int n, double segment) {
  Points q(n, 3);
  double arc = 0.0;
  for (int i = 0; i < n; ++i) {
    const double a = arc / 0.024;  // loop radius 2.4 cm
    q.row(i) << 0.024 * std::cos(a), 0.024 * std::sin(a), 0.01 * arc + 0.005 * std::sin(7.0 * arc);
    arc += segment * (i % 2 == 0 ? 1.5 : 0.5);
  }
  return q;
}

// Each sphere's arc position on the placed chain, against the reference: the chain's spacing
// is uniform along the true arc length to a small fraction of the spacing.
double WorstPlacementError(const SphereChain& chain, const spline::CatmullRom& curve,
                           const Points& q) {
  const double total = ReferenceArcLength(curve, q, 1.0);
  const int n = chain.size();
  double worst = 0.0;
  for (int k = 0; k < n; ++k) {
    const double wanted = total * k / (n - 1);
    worst = std::max(worst, std::abs(ReferenceArcLength(curve, q, chain.spheres()[k].s) - wanted));
  }
  return worst / chain.spacing();
}

TEST(SphereChain, SpheresAreUniformAlongTheTrueArcLength) {
  const int n = 60;
  const spline::CatmullRom curve(n);
  const Points q = CurvedStretchedTube(n, 0.016);
  SphereChain chain(curve, ReferenceArcLength(curve, q, 1.0), kRadius);
  chain.Place(q);
  // The table's straight lines between its entries (4 per segment) leave 2.3 % of a spacing here
  // (0.3 % where the points are evenly spread); spreading the spheres evenly in the curve
  // parameter instead would leave about half a spacing.
  EXPECT_LT(WorstPlacementError(chain, curve, q), 0.04);
  // And the same on the tube stretched by half along one axis (a pile pulled by a tool).
  Points stretched = q;
  stretched.col(0) *= 1.5;
  chain.Place(stretched);
  EXPECT_LT(WorstPlacementError(chain, curve, stretched), 0.05);
}

TEST(SphereChain, SpheresMoveContinuouslyWithTheCurve) {
  // The tube is stretched by a tenth and bent in 20000 small increments, its spheres sliding
  // along it across many table entries; re-placed at each, no sphere may move much farther than
  // the control points do (a sphere that jumped by even 1e-3 of a spacing when an interval or a
  // table entry changes hands would: each increment moves the points by 1e-5 of a spacing).
  const int n = 40;
  const spline::CatmullRom curve(n);
  const Points from = CurvedStretchedTube(n, 0.016);
  Points to = from;
  for (int i = 0; i < n; ++i)
    to.row(i) += Eigen::RowVector3d(0.1 * from(i, 0), 0.02 * from(i, 2), 0.0);
  SphereChain chain(curve, ReferenceArcLength(curve, from, 1.0), kRadius);
  chain.Place(from);
  std::vector<Vec3> last;
  for (const Sphere& sp : chain.spheres()) last.push_back(sp.centre);
  constexpr int kIncrements = 20000;
  const double point_move = (to - from).rowwise().norm().maxCoeff() / kIncrements;
  ASSERT_LT(point_move, 1.5e-5 * chain.spacing());
  double worst = 0.0;
  for (int step = 1; step <= kIncrements; ++step) {
    const double f = static_cast<double>(step) / kIncrements;
    chain.Place((1.0 - f) * from + f * to);
    for (int k = 0; k < chain.size(); ++k) {
      worst = std::max(worst, (chain.spheres()[k].centre - last[k]).norm());
      last[k] = chain.spheres()[k].centre;
    }
  }
  EXPECT_LT(worst, 10.0 * point_move);
  EXPECT_GT(worst, 0.0);
}

}  // namespace
}  // namespace viscera::collision
