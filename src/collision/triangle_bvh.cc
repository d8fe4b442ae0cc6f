#include "collision/triangle_bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "common/check.h"

namespace viscera::collision {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr int kLeafSize = 4;
constexpr int kMaxDepth = 60;  // median splits: depth <= log2(#F) + 1
// Beyond this shape factor L^2 / (2 A) (1.15 for an equilateral triangle) a triangle stays out of
// the tree: ClosestOnTriangle's barycentric coordinates lose too many digits to bound usefully.
constexpr double kMaxShape = 1e6;
// Far-field acceptance, a speed knob only (an estimate too loose to decide a sign falls back
// to the brute-force sum): the remainder bound may be at most this share of the subtree's
// largest possible solid angle A / gap^2, i.e. gap >= 2.07 radii. On the liver 0.3-0.7 cost
// within 25 % of each other; at 1.0 the accepted subtrees' bounds add up past the 2 pi margin
// and most signs needed the brute force.
constexpr double kFarFieldShare = 0.7;

struct TriangleGeometry {
  Vec3 a, b, c;
  Vec3 area_normal;  // A n = (b - a) x (c - a) / 2
  double longest_edge;
};

TriangleGeometry GeometryOf(const Points& v, const Triangles& f, int t) {
  TriangleGeometry g;
  g.a = v.row(f(t, 0));
  g.b = v.row(f(t, 1));
  g.c = v.row(f(t, 2));
  g.area_normal = 0.5 * (g.b - g.a).cross(g.c - g.a);
  g.longest_edge = std::max({(g.b - g.a).norm(), (g.c - g.b).norm(), (g.a - g.c).norm()});
  return g;
}

// L^2 / (2 A): the triangle's shape factor (inf when it has no area).
double ShapeFactor(const TriangleGeometry& g) {
  const double twice_area = 2.0 * g.area_normal.norm();
  return twice_area > 0.0 ? g.longest_edge * g.longest_edge / twice_area
                          : std::numeric_limits<double>::infinity();
}

}  // namespace

TriangleBvh::TriangleBvh(const Points& vertices, const Triangles& triangles, BoundScales scales)
    : vertices_(vertices), triangles_(triangles), scales_(scales) {
  coordinate_scale_ = vertices_.size() > 0 ? vertices_.cwiseAbs().maxCoeff() : 0.0;
  for (int t = 0; t < static_cast<int>(triangles_.rows()); ++t) {
    const TriangleGeometry g = GeometryOf(vertices_, triangles_, t);
    if (ShapeFactor(g) <= kMaxShape) {
      order_.push_back(t);
    } else {
      always_.push_back({g.a, g.b, g.c});
    }
  }
  if (!order_.empty()) {
    nodes_.reserve(2 * order_.size());
    Build(0, static_cast<int>(order_.size()), 0);
  }
  // the corners in leaf order: copies, so the very same doubles reach the triangle queries
  for (const int t : order_) {
    const TriangleGeometry g = GeometryOf(vertices_, triangles_, t);
    corners_.push_back({g.a, g.b, g.c});
  }
  // The brute force sums #F terms of at most 2 pi in triangle order, the hierarchy in another
  // order: each sum is within #F^2 eps 2 pi of the exact sum of its terms; the far triangles'
  // SolidAngle (well conditioned there: denominator ~ 4 d^3) within ~20 eps each. 1e-14 #F^2 + 1e-8
  // covers both with orders of magnitude to spare.
  const double f = static_cast<double>(triangles_.rows());
  rounding_slack_ = 1e-8 + 1e-14 * f * f;
}

int TriangleBvh::Build(int first, int count, int depth) {
  VISCERA_DEMAND(depth <= kMaxDepth);
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Node node;
  node.first = first;
  node.count = count;
  node.lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  node.hi = -node.lo;
  Vec3 centroid_lo = node.lo, centroid_hi = node.hi;
  for (int k = first; k < first + count; ++k) {
    const TriangleGeometry g = GeometryOf(vertices_, triangles_, order_[k]);
    for (const Vec3& x : {g.a, g.b, g.c}) {
      node.lo = node.lo.cwiseMin(x);
      node.hi = node.hi.cwiseMax(x);
    }
    const Vec3 centroid = (g.a + g.b + g.c) / 3.0;
    centroid_lo = centroid_lo.cwiseMin(centroid);
    centroid_hi = centroid_hi.cwiseMax(centroid);
  }
  node.centre = 0.5 * (node.lo + node.hi);
  node.dipole.setZero();
  node.quadrupole.setZero();
  for (int k = first; k < first + count; ++k) {
    const TriangleGeometry g = GeometryOf(vertices_, triangles_, order_[k]);
    for (const Vec3& x : {g.a, g.b, g.c})
      node.radius = std::max(node.radius, (x - node.centre).norm());
    node.area += g.area_normal.norm();
    node.dipole += g.area_normal;
    node.quadrupole += g.area_normal * ((g.a + g.b + g.c) / 3.0 - node.centre).transpose();
    node.longest_edge = std::max(node.longest_edge, g.longest_edge);
    const double shape = ShapeFactor(g);
    node.sliver = std::max(node.sliver, shape * shape / (g.longest_edge * g.longest_edge));
  }
  // the rounding of the sums above is far below the 1e-6 margin the remainder bound gets
  node.radius *= 1.0 + 1e-12;
  if (count > kLeafSize) {
    // median split along the centroids' longest side
    int axis = 0;
    (centroid_hi - centroid_lo).maxCoeff(&axis);
    const int half = count / 2;
    std::nth_element(order_.begin() + first, order_.begin() + first + half,
                     order_.begin() + first + count, [&](int s, int t) {
                       const auto centroid = [&](int u) {
                         return vertices_(triangles_(u, 0), axis) +
                                vertices_(triangles_(u, 1), axis) +
                                vertices_(triangles_(u, 2), axis);
                       };
                       return centroid(s) < centroid(t);
                     });
    node.left = Build(first, half, depth + 1);
    node.right = Build(first + half, count - half, depth + 1);
  }
  nodes_[index] = node;
  return index;
}

double TriangleBvh::DistanceLowerBound(const Node& node, const Vec3& p) const {
  const Vec3 outside = (node.lo - p).cwiseMax(p - node.hi).cwiseMax(0.0);
  const Vec3 farthest = (p - node.lo).cwiseAbs().cwiseMax((p - node.hi).cwiseAbs());
  const double box = outside.norm(), far = farthest.norm();
  // ClosestOnTriangle's answer strays from the triangle by at most (docs/contacts.md):
  //  - inside the face, through the barycentric coordinates (differences of products of dot
  //    products): per coordinate ~96 eps (L^2 / 2A)^2 R^2 / L^2, R the farthest vertex; 1000 here;
  //  - on an edge or a vertex, and in forming the point: a few eps of the coordinates and of R.
  const double barycentric = 1000.0 * kEps * node.sliver * far * far;
  if (barycentric > 0.1) return 0.0;  // too close to unbounded to reason about: never prune
  const double stray =
      2.0 * node.longest_edge * barycentric + 16.0 * kEps * (coordinate_scale_ + far);
  return std::max(0.0, box * (1.0 - 8.0 * kEps) - stray) * (1.0 - 8.0 * kEps) * scales_.distance;
}

double TriangleBvh::SquaredDistanceTo(const Corners& t, const Vec3& p) const {
  return SquaredDistanceToTriangle(p, t[0], t[1], t[2]);
}

double TriangleBvh::SolidAngleOf(const Corners& t, const Vec3& p) const {
  return SolidAngle(p, t[0], t[1], t[2]);
}

double TriangleBvh::NearestSquaredDistance(const Vec3& p) const {
  double best = std::numeric_limits<double>::infinity();
  for (const Corners& t : always_) best = std::min(best, SquaredDistanceTo(t, p));
  if (nodes_.empty()) return best;
  // Depth first, nearer child first. A subtree is skipped only when every triangle in it
  // computes a squared distance above `best`: such a triangle is neither the minimum nor tied.
  std::array<int, 2 * kMaxDepth + 2> stack;
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    const double bound = DistanceLowerBound(node, p);
    if (bound * bound > best) continue;
    if (node.left < 0) {
      for (int k = node.first; k < node.first + node.count; ++k)
        best = std::min(best, SquaredDistanceTo(corners_[k], p));
      continue;
    }
    const double left = DistanceLowerBound(nodes_[node.left], p),
                 right = DistanceLowerBound(nodes_[node.right], p);
    const bool left_first = left <= right;
    stack[top++] = left_first ? node.right : node.left;
    stack[top++] = left_first ? node.left : node.right;
  }
  return best;
}

TriangleBvh::SolidAngleEstimate TriangleBvh::MeshSolidAngle(const Vec3& p) const {
  SolidAngleEstimate estimate;
  for (const Corners& t : always_) estimate.value += SolidAngleOf(t, p);
  double remainder = 0.0;
  std::array<int, 2 * kMaxDepth + 2> stack;
  int top = 0;
  if (!nodes_.empty()) stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    // Far field: Omega = integral over the subtree of n . f(x), f(x) = (x - p) / |x - p|^3,
    // expanded about the centre c to second order. f = -grad(1/|x - p|), whose k-th derivatives
    // are bounded by k! / rho^(k+1) (Legendre polynomials are bounded by 1), so the remainder is
    // at most (3! / 2) r^2 / gap^4 per unit area: |error| <= 3 A r^2 / gap^4, gap = |p - c| - r.
    const Vec3 to_centre = node.centre - p;
    const double d = to_centre.norm(), gap = d - node.radius;
    if (gap > 0.0) {
      const double share = 3.0 * node.radius * node.radius / (gap * gap) * scales_.winding;
      if (share <= kFarFieldShare) {
        const Vec3 u = to_centre / d;
        const double dipole = u.dot(node.dipole) / (d * d);
        const double quadrupole =
            (node.quadrupole.trace() - 3.0 * u.dot(node.quadrupole * u)) / (d * d * d);
        estimate.value += dipole + quadrupole;
        remainder += share * node.area / (gap * gap);
        continue;
      }
    }
    if (node.left < 0) {
      for (int k = node.first; k < node.first + node.count; ++k)
        estimate.value += SolidAngleOf(corners_[k], p);
      continue;
    }
    stack[top++] = node.left;
    stack[top++] = node.right;
  }
  estimate.error = remainder * (1.0 + 1e-6) + rounding_slack_;
  return estimate;
}

}  // namespace viscera::collision
