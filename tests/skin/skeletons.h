#pragma once
/// Synthetic skeletons (control points, #N by 3) for the skin tests and benchmark, until the
/// mechanics can produce settled ones. Every path is resampled to N points uniform in arc
/// length.
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "common/types.h"

namespace viscera::skin::testing {

/// N points uniform in arc length along the path t -> path(t), t in [t0, t1] (dense polyline
/// of 200 N pieces).
inline Points ResampleByArcLength(const std::function<Vec3(double)>& path, double t0, double t1,
                                  int n) {
  const int dense = 200 * n;
  std::vector<Vec3> p(dense + 1);
  std::vector<double> arc(dense + 1, 0.0);
  for (int i = 0; i <= dense; ++i) {
    p[i] = path(t0 + (t1 - t0) * i / dense);
    if (i > 0) arc[i] = arc[i - 1] + (p[i] - p[i - 1]).norm();
  }
  Points q(n, 3);
  int k = 0;
  for (int i = 0; i < n; ++i) {
    const double target = arc.back() * i / (n - 1);
    while (k + 1 < dense && arc[k + 1] < target) ++k;
    const double span = arc[k + 1] - arc[k];
    const double f = span > 0.0 ? std::clamp((target - arc[k]) / span, 0.0, 1.0) : 0.0;
    q.row(i) = ((1.0 - f) * p[k] + f * p[k + 1]).transpose();
  }
  return q;
}

/// Straight tube along +x from the origin.
inline Points Straight(int n, double length) {
  Points q(n, 3);
  for (int i = 0; i < n; ++i) q.row(i) << length * i / (n - 1), 0.0, 0.0;
  return q;
}

/// Helix of the given radius and pitch (rise per turn) around +z.
inline Points Helix(int n, double radius, double pitch, double turns) {
  return ResampleByArcLength(
      [&](double t) {
        return Vec3(radius * std::cos(t), radius * std::sin(t),
                    pitch * t / (2.0 * std::numbers::pi));
      },
      0.0, 2.0 * std::numbers::pi * turns, n);
}

/// Hairpin: two straight arms of length `arm` along +x, centre lines `gap` apart in y,
/// joined at x = 0 by a half circle of radius gap / 2. The arms are not consecutive along
/// the tube (they are pi gap / 2 + arm apart along it at their far ends).
inline Points Hairpin(int n, double arm, double gap) {
  const double r = 0.5 * gap;
  const double half = std::numbers::pi * r;
  return ResampleByArcLength(
      [&](double t) {
        if (t < arm) return Vec3(arm - t, -r, 0.0);  // lower arm, towards the bend
        if (t < arm + half) {
          const double a = (t - arm) / r;  // 0..pi
          return Vec3(-r * std::sin(a), -r * std::cos(a), 0.0);
        }
        return Vec3(t - arm - half, r, 0.0);  // upper arm, away from the bend
      },
      0.0, 2.0 * arm + half, n);
}

/// A U-bend: arms of length `arm` and a half circle of radius `bend_radius`.
inline Points UBend(int n, double arm, double bend_radius) {
  return Hairpin(n, arm, 2.0 * bend_radius);
}

/// A right-angle bend in z = 0: `arm` along +x, a quarter circle of radius `bend_radius`,
/// `arm` along +y. Unlike a U-bend, its arms never come near each other, so a skin of it
/// that crosses itself does so at the bend (a fold), whatever the bend radius.
inline Points LBend(int n, double arm, double bend_radius) {
  const double quarter = 0.5 * std::numbers::pi * bend_radius;
  return ResampleByArcLength(
      [&](double t) -> Vec3 {
        if (t < arm) return Vec3(t, 0.0, 0.0);
        if (t < arm + quarter) {
          const double a = (t - arm) / bend_radius;
          return Vec3(arm + bend_radius * std::sin(a), bend_radius * (1.0 - std::cos(a)), 0.0);
        }
        return Vec3(arm + bend_radius, bend_radius + (t - arm - quarter), 0.0);
      },
      0.0, 2.0 * arm + quarter, n);
}

/// Flat Archimedean spiral in z = 0 of total length `length`, starting at radius r0 with
/// `spacing` between the centre lines of neighbouring turns: the "packed" stand-in for the
/// settled fall scene (4 m, 250 control points, turns 2.2-2.6 R apart).
inline Points FlatSpiral(int n, double length, double r0, double spacing) {
  const double b = spacing / (2.0 * std::numbers::pi);
  // length of r = r0 + b theta from 0 to theta, approximately integral of r dtheta
  auto arc = [&](double theta) { return r0 * theta + 0.5 * b * theta * theta; };
  double hi = 1.0;
  while (arc(hi) < length) hi *= 2.0;
  double lo = 0.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (arc(mid) < length ? lo : hi) = mid;
  }
  Points q = ResampleByArcLength(
      [&](double t) { return Vec3((r0 + b * t) * std::cos(t), (r0 + b * t) * std::sin(t), 0.0); },
      0.0, hi, n);
  return q;
}

/// Closest distance from p to the polyline through `curve` (#M by 3 dense samples), and the
/// index of the closest piece.
inline double DistanceToPolyline(const std::vector<Vec3>& curve, const Vec3& p,
                                 int* piece = nullptr) {
  double best = 1e300;
  for (size_t i = 0; i + 1 < curve.size(); ++i) {
    const Vec3 d = curve[i + 1] - curve[i];
    const double t =
        std::clamp((p - curve[i]).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
    const double dist = (curve[i] + t * d - p).norm();
    if (dist < best) {
      best = dist;
      if (piece) *piece = static_cast<int>(i);
    }
  }
  return best;
}

}  // namespace viscera::skin::testing
