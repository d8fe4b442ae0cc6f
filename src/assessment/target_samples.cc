#include "assessment/target_samples.h"

#include <cmath>
#include <numbers>

namespace viscera::assessment {
namespace {

// Two unit vectors spanning the plane normal to n.
void Basis(const Vec3& n, Vec3* u, Vec3* v) {
  const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  *u = n.cross(helper).normalized();
  *v = n.cross(*u);
}

// Even-odd rule in the plane's 2-D coordinates.
bool InsidePolygon(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  bool inside = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

}  // namespace

Vec3 PolygonNormal(const std::vector<Vec3>& corners) {
  Vec3 n = Vec3::Zero();
  for (size_t i = 0; i < corners.size(); ++i)
    n += corners[i].cross(corners[(i + 1) % corners.size()]);
  const double size = n.norm();
  return size > 0.0 ? Vec3(n / size) : Vec3(Vec3::Zero());
}

double PolygonArea(const std::vector<Vec3>& corners) {
  Vec3 n = Vec3::Zero();
  for (size_t i = 0; i < corners.size(); ++i)
    n += corners[i].cross(corners[(i + 1) % corners.size()]);
  return 0.5 * n.norm();
}

std::vector<Vec3> TargetSamples(const mechanics::TargetParams& target) {
  Vec3 u, v;
  Basis(target.normal, &u, &v);
  std::vector<Vec3> out;
  const int n = std::max(1, target.samples);
  if (target.polygon.empty()) {
    // Vogel: r_k = R sqrt((k + 1/2) / n), angle k * golden angle
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (int k = 0; k < n; ++k) {
      const double r = target.radius * std::sqrt((k + 0.5) / n);
      const double a = golden * k;
      out.push_back(target.centre + r * (std::cos(a) * u + std::sin(a) * v));
    }
    return out;
  }
  std::vector<Eigen::Vector2d> poly;
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const Vec3& c : target.polygon) {
    const Vec3 d = c - target.centre;
    poly.emplace_back(d.dot(u), d.dot(v));
    lo = lo.cwiseMin(poly.back());
    hi = hi.cwiseMax(poly.back());
  }
  // a grid of spacing sqrt(area / n) puts about n points inside; cell centres
  const double spacing = std::sqrt(PolygonArea(target.polygon) / n);
  for (double y = lo.y() + 0.5 * spacing; y < hi.y(); y += spacing) {
    for (double x = lo.x() + 0.5 * spacing; x < hi.x(); x += spacing) {
      if (InsidePolygon(poly, {x, y})) out.push_back(target.centre + x * u + y * v);
    }
  }
  if (out.empty()) out.push_back(target.centre);
  return out;
}

}  // namespace viscera::assessment
