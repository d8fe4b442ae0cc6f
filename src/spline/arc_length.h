#pragma once
/// Arc-length table of a Catmull-Rom curve: cumulative length at regularly spaced curve
/// parameters, and its inverse (the curve parameter at a given arc length). Used to spread
/// collision spheres and skin rings uniformly along the curve.
///
/// Between entries, arc length is not a straight line but the integral of the speed |dP/du|
/// interpolated by the cubic through its values at the interval's 4 Gauss-Lobatto nodes (a
/// quartic; at the interval's end, the Lobatto rule itself, exact to degree 5). Its error falls
/// as the fifth power of the interval, so 2 intervals per segment place the sphere chain (re-placed
/// at every step) 100 times more uniformly than 4 straight-line intervals did, with 7 speed
/// evaluations per segment instead of 12 (tests/collision/sphere_chain_test.cc). The quartic is
/// monotone while the speed's interpolant stays positive: anywhere but at a near-cusp.
#include <array>
#include <vector>

#include "common/types.h"
#include "spline/catmull_rom.h"

namespace viscera::spline {

class ArcLengthTable {
 public:
  /// @param samples_per_segment intervals per segment, >= 1.
  explicit ArcLengthTable(int samples_per_segment = 8) : samples_per_segment_(samples_per_segment) {}

  /// Rebuilds the table for pose q. Reuses its buffers: no allocation once sized.
  void Build(const CatmullRom& curve, const Points& q);

  double total_length() const { return cumulative_.empty() ? 0.0 : cumulative_.back(); }

  /// Arc length from s = 0 to s (m): continuous and non-decreasing in s, and in q.
  double ArcLengthAt(double s) const;

  /// Curve parameter whose arc length from the start is `arc` (clamped to the curve): the
  /// inverse of ArcLengthAt to 3e-4 of an interval where the control points are spread 3 to 1
  /// (2 um on the cavity's tube), 2e-7 where they are even; continuous in arc and in q.
  double ParameterAt(double arc) const;
  /// Same, with `interval` the table interval it found (in and out): a hint that makes a sweep
  /// in increasing arc cost O(1) per call instead of a search.
  double ParameterAt(double arc, size_t* interval) const;

 private:
  // Arc length at t in [0, 1] of interval i (between entries i and i + 1).
  double Interpolate(size_t i, double t) const;

  int samples_per_segment_;
  std::vector<double> cumulative_;  // arc length at s = i / (#entries - 1)
  // Interval i's arc length beyond entry i as c0 t + c1 t^2 + c2 t^3 + c3 t^4, t in [0, 1]: the
  // integral of the cubic through the speeds at the interval's 4 Gauss-Lobatto nodes.
  std::vector<std::array<double, 4>> poly_;
};

}  // namespace viscera::spline
