#include "render/target_patch.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace viscera::render {

void AppendTargetPatch(const mechanics::TargetParams& target, TriMesh* out) {
  const Vec3 lift = kTargetLift * target.normal;
  std::vector<Vec3> rim = target.polygon;
  if (rim.empty()) {
    // a disc: 48 sides (the rim's sag is 0.2 % of the radius)
    const Vec3 helper = std::abs(target.normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 u = target.normal.cross(helper).normalized();
    const Vec3 v = target.normal.cross(u);
    constexpr int kSides = 48;
    for (int k = 0; k < kSides; ++k) {
      const double a = 2.0 * std::numbers::pi * k / kSides;
      rim.push_back(target.centre + target.radius * (std::cos(a) * u + std::sin(a) * v));
    }
  }
  const uint32_t base = static_cast<uint32_t>(out->positions.size());
  const Eigen::Vector3f n = target.normal.cast<float>();
  out->positions.push_back((target.centre + lift).cast<float>());
  out->normals.push_back(n);
  for (const Vec3& p : rim) {
    out->positions.push_back((p + lift).cast<float>());
    out->normals.push_back(n);
  }
  // a fan from the centre; counter-clockwise seen from the normal's side
  const Vec3 first = rim[0] - target.centre, second = rim[1 % rim.size()] - target.centre;
  const bool ccw = first.cross(second).dot(target.normal) >= 0.0;
  const uint32_t m = static_cast<uint32_t>(rim.size());
  for (uint32_t k = 0; k < m; ++k) {
    const uint32_t a = base + 1 + k, b = base + 1 + (k + 1) % m;
    out->indices.insert(out->indices.end(), {base, ccw ? a : b, ccw ? b : a});
  }
}

}  // namespace viscera::render
