#pragma once
/// Sampling a triangle mesh's signed distance on a regular grid: the distance to the nearest
/// triangle, negative where the generalized winding number is above 1/2 (inside a closed,
/// outward-oriented mesh; robust to small holes). Two builders give bit-identical samples: the
/// brute force (every grid point against every triangle; the reference) and the hierarchy
/// (collision/triangle_bvh.h), which MeshSdf uses.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "collision/triangle_bvh.h"

namespace viscera::collision {

/// Grid points origin + cell (i, j, k), 0 <= i < nx, ...; samples stored x fastest.
struct SdfGrid {
  Vec3 origin = Vec3::Zero();  ///< m
  double cell = 0.0;           ///< m
  int nx = 0, ny = 0, nz = 0;
  size_t size() const { return static_cast<size_t>(nx) * ny * nz; }
  Vec3 Point(int i, int j, int k) const { return origin + cell * Vec3(i, j, k); }
};

/// The grid around `vertices` (#V by 3): `resolution` cells along the box's longest side, padded
/// by 3 cells on every side. @pre the box has a positive, finite longest side.
SdfGrid GridAround(const Points& vertices, int resolution);

/// Every grid point against every triangle (#F by 3 indices into `vertices`).
std::vector<double> SampleBruteForce(const Points& vertices, const Triangles& triangles,
                                     const SdfGrid& grid);

struct SamplingStats {
  int64_t exact_signs = 0;  ///< points whose sign needed the brute-force winding number
};

/// The same samples as SampleBruteForce, bit for bit, through a TriangleBvh: the distance is the
/// very same minimum; the sign is decided by the hierarchy's solid angle when its error bound
/// keeps it clear of the threshold (2 pi), else by the brute-force sum itself.
/// `scales` exists for the tests' negative controls (TriangleBvh::BoundScales).
std::vector<double> SampleWithHierarchy(const Points& vertices, const Triangles& triangles,
                                        const SdfGrid& grid, TriangleBvh::BoundScales scales = {},
                                        SamplingStats* stats = nullptr);

}  // namespace viscera::collision
