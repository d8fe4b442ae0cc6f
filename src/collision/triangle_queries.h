#pragma once
/// Point-triangle queries behind mesh obstacles' distance fields. Defined out of line in one
/// translation unit on purpose: the brute-force and the hierarchical field builders call the
/// very same compiled code, so equal inputs give bit-identical outputs (docs/contacts.md,
/// "Mesh obstacles").
#include "common/types.h"

namespace viscera::collision {

/// #F by 3 vertex indices, one triangle per row.
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Closest point to `p` on triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 ClosestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// (ClosestOnTriangle(p, a, b, c) - p).squaredNorm() (m^2).
double SquaredDistanceToTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Signed solid angle (sr) of triangle (a, b, c) seen from `p` (Van Oosterom & Strackee 1983):
/// positive when `p` is behind the triangle, i.e. on the side (b - a) x (c - a) points away from.
/// In (-2 pi, 2 pi].
double SolidAngle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace viscera::collision
