#include "scene/shapes.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/check.h"

namespace viscera::scene {
namespace {

Vec3 Unit(const TomlReader& r, const std::string& key, const Vec3& fallback) {
  const Vec3 v = r.Vector(key, fallback);
  ThrowUnless(v.norm() > 1e-12, r.Name(key), " = [", v.transpose(), "]: must not be zero");
  return v.normalized();
}

// A unit vector perpendicular to `axis`.
Vec3 AnyPerpendicular(const Vec3& axis) {
  const Vec3 trial = std::abs(axis.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX();
  return axis.cross(trial).normalized();
}

// Resamples a dense polyline to n points at equal arc length, spanning `length` from its start.
Points Resample(const std::vector<Vec3>& dense, int n, double length) {
  Points q(n, 3);
  double walked = 0.0;
  size_t k = 0;
  for (int i = 0; i < n; ++i) {
    const double target = length * i / (n - 1);
    while (k + 1 < dense.size() && walked + (dense[k + 1] - dense[k]).norm() < target) {
      walked += (dense[k + 1] - dense[k]).norm();
      ++k;
    }
    if (k + 1 >= dense.size()) {
      q.row(i) = dense.back().transpose();
      continue;
    }
    const double piece = (dense[k + 1] - dense[k]).norm();
    const double f = piece > 0.0 ? (target - walked) / piece : 0.0;
    q.row(i) = (dense[k] + f * (dense[k + 1] - dense[k])).transpose();
  }
  return q;
}

}  // namespace

Points MakeShape(const TomlReader& r, int n, double length) {
  const std::string kind = r.String("kind");
  if (kind == "points") {
    Points q = r.PointList("points");
    ThrowUnless(n == 0 || q.rows() == n, r.Name("points"), " has ", q.rows(),
                " points but intestine.control_points = ", n, ": they must agree");
    r.Finish();
    return q;
  }
  ThrowUnless(n >= 4, "intestine.control_points = ", n,
              ": need at least 4 (required unless shape.kind = \"points\")");
  const double spacing = length / (n - 1);
  Points q(n, 3);
  if (kind == "straight") {
    const Vec3 start = r.Vector("start", Vec3::Zero());
    const Vec3 dir = Unit(r, "direction", Vec3::UnitX());
    for (int i = 0; i < n; ++i) q.row(i) = (start + i * spacing * dir).transpose();
  } else if (kind == "helix") {
    // Axis through `center`; the coil starts at center + radius * e1 and rises `pitch` per turn.
    const Vec3 center = r.Vector("center", Vec3::Zero());
    const Vec3 axis = Unit(r, "axis", Vec3::UnitZ());
    const double radius = r.Double("radius");
    const double pitch = r.Double("pitch");
    ThrowUnless(radius > 0.0, r.Name("radius"), " = ", radius, ": must be > 0");
    const Vec3 e1 = AnyPerpendicular(axis), e2 = axis.cross(e1);
    const double rise = pitch / (2.0 * M_PI);  // m per radian
    const double arc_per_radian = std::sqrt(radius * radius + rise * rise);
    for (int i = 0; i < n; ++i) {
      const double theta = i * spacing / arc_per_radian;
      q.row(i) =
          (center + radius * (std::cos(theta) * e1 + std::sin(theta) * e2) + rise * theta * axis)
              .transpose();
    }
  } else if (kind == "serpentine") {
    // A planar sine wave along `direction`, swinging along `lateral`.
    const Vec3 start = r.Vector("start", Vec3::Zero());
    const Vec3 dir = Unit(r, "direction", Vec3::UnitX());
    Vec3 lateral = r.Vector("lateral", AnyPerpendicular(dir));
    lateral -= lateral.dot(dir) * dir;
    ThrowUnless(lateral.norm() > 1e-12, r.Name("lateral"), ": must not be parallel to direction");
    lateral.normalize();
    const double amplitude = r.Double("amplitude");
    const double wavelength = r.Double("wavelength");
    ThrowUnless(wavelength > 0.0, r.Name("wavelength"), " = ", wavelength, ": must be > 0");
    std::vector<Vec3> dense;
    double arc = 0.0;
    const double dx = wavelength / 2000.0;
    for (double x = 0.0; arc <= length * (1.0 + 1e-9) || dense.size() < 2; x += dx) {
      const Vec3 p = start + x * dir + amplitude * std::sin(2.0 * M_PI * x / wavelength) * lateral;
      if (!dense.empty()) arc += (p - dense.back()).norm();
      dense.push_back(p);
    }
    q = Resample(dense, n, length);
  } else {
    Fail(r.Name("kind"), " = \"", kind,
         "\": expected \"straight\", \"helix\", \"serpentine\" or \"points\"");
  }
  r.Finish();
  return q;
}

StartOverlap DeepestStartOverlap(const Points& q,
                                 const std::vector<collision::Obstacle>& obstacles) {
  StartOverlap deepest;
  for (size_t k = 0; k < obstacles.size(); ++k) {
    const collision::PreparedObstacle obstacle(obstacles[k]);
    Vec3 normal;
    for (int i = 0; i < q.rows(); ++i) {
      const double depth = -obstacle.SignedDistance(q.row(i).transpose(), &normal);
      if (depth > deepest.depth) deepest = {i, k, depth};
    }
  }
  return deepest;
}

void CheckStartClear(const Points& q, double radius,
                     const std::vector<collision::Obstacle>& obstacles) {
  const StartOverlap o = DeepestStartOverlap(q, obstacles);
  if (o.point < 0 || o.depth <= radius) return;
  const collision::Obstacle& obstacle = obstacles[o.obstacle];
  const auto mm = [](double m) { return std::lround(m * 1e4) / 10.0; };
  Fail("intestine.shape: control point ", o.point, " of ", q.rows(),
       " (s = ", std::lround(1e3 * o.point / std::max<double>(q.rows() - 1, 1)) / 1e3, ") starts ",
       mm(o.depth), " mm ", obstacle.inside ? "outside" : "inside", " obstacle \"", obstacle.name,
       "\"", obstacle.inside ? " (inside = true: the tube belongs inside it)" : "",
       ", more than the tube's radius (", mm(radius),
       " mm): the whole tube is past the obstacle's surface there, and the contacts would throw "
       "it back over the first steps (seconds of CPU each); place the shape in the free space");
}

}  // namespace viscera::scene
