#pragma once
/// The narrow phase of two sphere centres: their distance and the unit normal from b to a. The
/// contacts compute it for every self pair of the Verlet list (most of them far apart) at every
/// re-placement of the chain, so it comes four pairs at a time too.
#include <algorithm>
#include <array>

#include <Eigen/Core>

#include "common/types.h"

namespace viscera::collision {

struct PairSeparation {
  double distance = 0.0;        ///< |a - b| (m)
  Vec3 normal = Vec3::UnitZ();  ///< (a - b) / |a - b|; +z when |a - b| <= 1e-12
};

/// One pair: d = a - b, |d| (Eigen's norm: sqrt((x^2 + y^2) + z^2)), d times 1/|d|.
inline PairSeparation Separation(const Vec3& a, const Vec3& b) {
  const Vec3 d = a - b;
  const double distance = d.norm();
  return {distance, distance > 1e-12 ? Vec3(d * (1.0 / distance)) : Vec3::UnitZ()};
}

/// `count` (1 to 4) pairs at once, Separation's operations lane by lane (IEEE's packed square
/// root and division round as the scalar ones do): the same bits, with the pairs' square root and
/// division latencies overlapped. Lanes past `count` repeat the last pair; out[0..count) is set.
inline void Separations(const std::array<const Vec3*, 4>& a, const std::array<const Vec3*, 4>& b,
                        int count, PairSeparation* out) {
  using Lanes = Eigen::Array4d;
  Lanes dx, dy, dz;
  for (int l = 0; l < 4; ++l) {
    const int k = std::min(l, count - 1);
    const Vec3 d = *a[k] - *b[k];
    dx[l] = d.x();
    dy[l] = d.y();
    dz[l] = d.z();
  }
  const Lanes distance = ((dx * dx + dy * dy) + dz * dz).sqrt();
  const Lanes inv = Lanes::Ones() / distance;
  const Lanes nx = dx * inv, ny = dy * inv, nz = dz * inv;
  for (int l = 0; l < count; ++l) {
    out[l].distance = distance[l];
    out[l].normal = distance[l] > 1e-12 ? Vec3(nx[l], ny[l], nz[l]) : Vec3::UnitZ();
  }
}

}  // namespace viscera::collision
