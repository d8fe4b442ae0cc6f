#include "collision/obstacle.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace viscera::collision {
namespace {

Vec3 SafeNormalize(const Vec3& v, const Vec3& fallback) {
  const double n = v.norm();
  return n > 1e-12 ? Vec3(v * (1.0 / n)) : fallback;
}

// Distance from p to the solid (positive outside), normal outward; `f` is FrameOf(o).
double SolidDistance(const Obstacle& o, const PreparedObstacle::Frame& f, const Vec3& p,
                     Vec3* normal) {
  switch (o.kind) {
    case ObstacleKind::kPlane: {
      *normal = o.normal;
      return o.normal.dot(p - o.point);
    }
    case ObstacleKind::kSphere: {
      const Vec3 d = p - o.centre;
      *normal = SafeNormalize(d, Vec3::UnitZ());
      return d.norm() - o.radius;
    }
    case ObstacleKind::kCapsule: {
      const Vec3 ab = o.b - o.a;
      const double t = std::clamp((p - o.a).dot(ab) / std::max(ab.squaredNorm(), 1e-24), 0.0, 1.0);
      const Vec3 d = p - (o.a + t * ab);
      *normal = SafeNormalize(d, Vec3::UnitZ());
      return d.norm() - o.radius;
    }
    case ObstacleKind::kBox: {
      // In the box frame: outside, distance to the nearest point; inside, to the nearest face.
      const Mat3& r = f.rotation;
      const Vec3 local = r.transpose() * (p - o.centre);
      const Vec3 q = local.cwiseAbs() - o.half_extents;
      if (q.maxCoeff() > 0.0) {
        const Vec3 outside = q.cwiseMax(0.0);
        Vec3 n_local = outside.cwiseProduct(local.cwiseSign());
        *normal = r * SafeNormalize(n_local, Vec3::UnitZ());
        return outside.norm();
      }
      int axis;
      const double d = q.maxCoeff(&axis);
      Vec3 n_local = Vec3::Zero();
      n_local(axis) = local(axis) >= 0.0 ? 1.0 : -1.0;
      *normal = r * n_local;
      return d;
    }
    case ObstacleKind::kEllipsoid: {
      // k0 = |p/r|, k1 = |p/r^2|: d ~ k0 (k0 - 1) / k1 (exact on the surface), normal along the
      // gradient p / r^2.
      const Mat3& r = f.rotation;
      const Vec3 local = r.transpose() * (p - o.centre);
      // (Every sphere of the tube queries its cavity at every step: 1 division, not 10.)
      const Vec3& inv_radii = f.inv_radii;
      const Vec3 scaled = local.cwiseProduct(inv_radii);
      const Vec3 grad = scaled.cwiseProduct(inv_radii);
      const double k0 = scaled.norm(), k1 = grad.norm();
      const double inv_k1 = 1.0 / k1;
      *normal = k1 > 1e-12 ? Vec3(r * (grad * inv_k1)) : Vec3(r * Vec3::UnitZ());
      if (k1 < 1e-12) return -o.radii.minCoeff();
      return k0 * (k0 - 1.0) * inv_k1;
    }
    case ObstacleKind::kMesh: return o.sdf->Distance(p, normal);
  }
  return 0.0;
}

double Signed(const Obstacle& o, const PreparedObstacle::Frame& f, const Vec3& p, Vec3* normal) {
  const double d = SolidDistance(o, f, p, normal);
  if (!o.inside) return d;
  *normal = -*normal;
  return -d;
}

}  // namespace

PreparedObstacle::Frame PreparedObstacle::FrameOf(const Obstacle& o) {
  Frame f;
  if (o.kind == ObstacleKind::kBox || o.kind == ObstacleKind::kEllipsoid)
    f.rotation = o.orientation.toRotationMatrix();
  if (o.kind == ObstacleKind::kEllipsoid) f.inv_radii = o.radii.cwiseInverse();
  return f;
}

PreparedObstacle::PreparedObstacle(Obstacle obstacle)
    : obstacle_(std::move(obstacle)), frame_(FrameOf(obstacle_)) {}

double PreparedObstacle::SignedDistance(const Vec3& p, Vec3* normal) const {
  return Signed(obstacle_, frame_, p, normal);
}

double SignedDistance(const Obstacle& o, const Vec3& p, Vec3* normal) {
  return Signed(o, PreparedObstacle::FrameOf(o), p, normal);
}

double SignedDistance(const Obstacle& o, const Vec3& p) {
  if (o.kind == ObstacleKind::kMesh) return o.inside ? -o.sdf->Distance(p) : o.sdf->Distance(p);
  Vec3 normal;
  return SignedDistance(o, p, &normal);
}

}  // namespace viscera::collision
