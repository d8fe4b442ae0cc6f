#pragma once
/// Arc-length table of a Catmull-Rom curve: cumulative length at regularly spaced curve
/// parameters, and its inverse (the curve parameter at a given arc length). Used to spread
/// collision spheres and skin rings uniformly along the curve.
#include <vector>

#include "common/types.h"
#include "spline/catmull_rom.h"

namespace viscera::spline {

class ArcLengthTable {
 public:
  /// @param samples_per_segment sub-intervals per segment (each integrated with 3-point
  ///        Gauss-Legendre), >= 1.
  explicit ArcLengthTable(int samples_per_segment = 8)
      : samples_per_segment_(samples_per_segment) {}

  /// Rebuilds the table for pose q. Reuses its buffers: no allocation once sized.
  void Build(const CatmullRom& curve, const Points& q);

  double total_length() const { return cumulative_.empty() ? 0.0 : cumulative_.back(); }

  /// Arc length from s = 0 to s (m), linear between table entries.
  double ArcLengthAt(double s) const;

  /// Curve parameter whose arc length from the start is `arc` (clamped to the curve).
  double ParameterAt(double arc) const;
  /// Same, with `interval` the table interval it found (in and out): a hint that makes a sweep
  /// in increasing arc cost O(1) per call instead of a binary search. Same result.
  double ParameterAt(double arc, size_t* interval) const;

 private:
  int samples_per_segment_;
  std::vector<double> cumulative_;  // arc length at s = i / (#entries - 1)
};

}  // namespace viscera::spline
