#pragma once
/// Helpers shared by the skin tests: dense samples of the skeleton curve.
#include <vector>

#include "common/types.h"
#include "spline/catmull_rom.h"

namespace viscera::skin::testing {

/// The Catmull-Rom curve of q sampled `per_segment` times per segment (#samples points).
inline std::vector<Vec3> DenseCurve(const Points& q, int per_segment = 40) {
  const spline::CatmullRom curve(static_cast<int>(q.rows()));
  const int count = curve.num_segments() * per_segment + 1;
  std::vector<Vec3> out(count);
  for (int i = 0; i < count; ++i) out[i] = curve.Position(q, static_cast<double>(i) / (count - 1));
  return out;
}

}  // namespace viscera::skin::testing
