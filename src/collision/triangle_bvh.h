#pragma once
/// A bounding-volume hierarchy over a triangle mesh, for the two sums a mesh obstacle's distance
/// field takes at every grid point (collision/sdf_sampling.h): the nearest triangle's squared
/// distance and the solid angle of the whole mesh. Both answer what the brute-force loop over
/// every triangle answers, by bounds that are proven rather than tuned:
///  - the nearest squared distance is the very same double: a subtree is skipped only when its
///    box is farther than the best distance so far by more than the rounding of
///    ClosestOnTriangle can account for;
///  - the solid angle comes with an error bound: near triangles are summed exactly
///    (SolidAngle), far subtrees by a second-order multipole expansion whose Taylor remainder is
///    bounded (docs/contacts.md, "Mesh obstacles", gives the derivation).
#include <array>
#include <vector>

#include "collision/triangle_queries.h"

namespace viscera::collision {

/// Multipliers of TriangleBvh's two proven bounds: 1 is the proof. Other values exist for the
/// tests' negative controls only (a wrong bound must change the field, or the tests prove nothing).
struct BvhBoundScales {
  double distance = 1.0;  ///< multiplies a subtree's lower bound on the distance (> 1: wrong)
  double winding = 1.0;   ///< multiplies a far subtree's remainder bound (< 1: wrong)
};

class TriangleBvh {
 public:
  using BoundScales = BvhBoundScales;

  /// @pre every index in `triangles` (#F by 3) is a row of `vertices` (#V by 3), all finite.
  TriangleBvh(const Points& vertices, const Triangles& triangles, BoundScales scales = {});

  /// The minimum over every triangle of (ClosestOnTriangle(p, a, b, c) - p).squaredNorm(), as
  /// the same double the brute-force std::min over all triangles gives (+inf without triangles).
  double NearestSquaredDistance(const Vec3& p) const;

  struct SolidAngleEstimate {
    double value = 0.0;  ///< sr
    double error =
        0.0;  ///< sr: bounds |value - the brute-force sum of SolidAngle in triangle order|
  };
  /// The solid angle of the whole mesh seen from `p` (4 pi times its winding number).
  SolidAngleEstimate MeshSolidAngle(const Vec3& p) const;

  /// Subtrees of the hierarchy (for the tests and the benchmark).
  int nodes() const { return static_cast<int>(nodes_.size()); }

 private:
  struct Node {
    Vec3 lo, hi;                // box of the node's vertices
    Vec3 centre;                // the expansion's centre (the box's)
    double radius = 0.0;        // every vertex lies within radius of centre (m)
    double area = 0.0;          // sum of the triangles' areas (m^2)
    Vec3 dipole;                // sum of A_t n_t (m^2)
    Mat3 quadrupole;            // sum of A_t n_t (g_t - centre)^T, g_t the centroid (m^3)
    double longest_edge = 0.0;  // m
    double sliver = 0.0;        // max over triangles of (L_t^2 / (2 A_t))^2 / L_t^2 (1/m^2)
    int first = 0, count = 0;   // a leaf's triangles: order_[first, first + count)
    int left = -1, right = -1;  // children, -1 in a leaf
  };

  using Corners = std::array<Vec3, 3>;

  int Build(int first, int count, int depth);
  // A lower bound on the computed distance from p to any triangle under `node` (m), or 0.
  double DistanceLowerBound(const Node& node, const Vec3& p) const;
  double SquaredDistanceTo(const Corners& triangle, const Vec3& p) const;
  double SolidAngleOf(const Corners& triangle, const Vec3& p) const;

  Points vertices_;
  Triangles triangles_;
  BoundScales scales_;
  std::vector<Node> nodes_;
  std::vector<int> order_;        // triangle indices, grouped by leaf
  std::vector<Corners> corners_;  // their corners, in the same order
  std::vector<Corners> always_;   // (near-)degenerate triangles: outside the tree, always evaluated
  double coordinate_scale_ = 0.0;  // largest |vertex coordinate| (m)
  double rounding_slack_ = 0.0;    // sr: the two sums' rounding, added to every error
};

}  // namespace viscera::collision
