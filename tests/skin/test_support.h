#pragma once
/// Helpers shared by the skin tests: dense samples of the skeleton curve.
#include <vector>

#include "common/types.h"
#include "skin/mesh.h"
#include "skin/tube_rays.h"
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

/// Ring folds of a ring-based mesh: steps from ring i to ring i + 1 along one side line
/// that do not advance along the curve (the rings cross there).
inline int BackwardRingSteps(const TubeRays& rays, const Mesh& mesh) {
  int backward = 0;
  for (int i = 0; i + 1 < rays.num_rings(); ++i) {
    const Vec3 step = rays.ring_centers()[i + 1] - rays.ring_centers()[i];
    for (int j = 0; j < rays.sides(); ++j) {
      if ((mesh.positions[rays.TubeVertex(i + 1, j)] - mesh.positions[rays.TubeVertex(i, j)])
              .dot(step) <= 0.0) {
        ++backward;
      }
    }
  }
  return backward;
}

}  // namespace viscera::skin::testing
