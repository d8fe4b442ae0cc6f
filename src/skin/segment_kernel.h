#pragma once
/// The closed-form convolution kernel of a line segment (Hornus, Angelidis, Cani,
/// "Implicit modeling using subdivision curves", The Visual Computer 2003; France et al.
/// 2005, eq. 1):
///
///   f(p) = integral over the segment of dl / |p - x(l)|^3 = (sin a1 - sin a2) / d(p, H)^2
///
/// with H the projection of p on the segment's line, d = |p - H|, and a1, a2 the signed
/// angles at p between pH and the lines to the two end points. With x the signed coordinate
/// of an end point along the segment measured from H, sin a = x / sqrt(d^2 + x^2).
#include <algorithm>
#include <cmath>

#include "common/types.h"

namespace viscera::skin {

/// A skeleton segment: start point, unit direction, length (m).
struct KernelSegment {
  Vec3 start = Vec3::Zero();
  Vec3 direction = Vec3::UnitX();
  double length = 0.0;
};

/// Field of one segment at p, (sin a1 - sin a2) / d^2 (1/m^2). d^2 is floored at
/// `min_d2` so that points on the segment's line give a large finite value.
inline double SegmentField(const KernelSegment& seg, const Vec3& p, double min_d2) {
  const Vec3 w = p - seg.start;
  const double t = w.dot(seg.direction);  // coordinate of H from the start
  const double d2 = std::max(w.squaredNorm() - t * t, min_d2);
  const double x1 = seg.length - t, x0 = -t;  // end points seen from H
  const double sin1 = x1 / std::sqrt(d2 + x1 * x1);
  const double sin0 = x0 / std::sqrt(d2 + x0 * x0);
  return (sin1 - sin0) / d2;
}

/// Iso-value that puts the surface at distance `radius` from a straight skeleton covering
/// the arc-length offsets [lo, hi] around the attachment point (lo <= 0 <= hi), measured
/// perpendicular to it: (sin a1 - sin a2) / R^2 with sin a = x / sqrt(R^2 + x^2).
inline double StraightIsoValue(double radius, double lo, double hi) {
  const double r2 = radius * radius;
  return (hi / std::sqrt(r2 + hi * hi) - lo / std::sqrt(r2 + lo * lo)) / r2;
}

}  // namespace viscera::skin
