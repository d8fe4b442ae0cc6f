#include "collision/sdf_sampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace viscera::collision {
namespace {

// The brute-force winding number's decision, summed in triangle order (as MeshSdf always did).
bool InsideByWinding(const Points& v, const Triangles& f, const Vec3& p) {
  double winding = 0.0;
  for (Eigen::Index t = 0; t < f.rows(); ++t)
    winding += SolidAngle(p, v.row(f(t, 0)), v.row(f(t, 1)), v.row(f(t, 2)));
  // ~1 inside a closed, outward-oriented mesh, ~0 outside
  return std::abs(winding) / (4.0 * M_PI) > 0.5;
}

double Signed(bool inside, double squared_distance) {
  return (inside ? -1.0 : 1.0) * std::sqrt(squared_distance);
}

}  // namespace

SdfGrid GridAround(const Points& vertices, int resolution) {
  const Vec3 lo = vertices.colwise().minCoeff().transpose(),
             hi = vertices.colwise().maxCoeff().transpose();
  SdfGrid grid;
  grid.cell = (hi - lo).maxCoeff() / resolution;
  const double pad = 3.0 * grid.cell;
  grid.origin = lo - Vec3::Constant(pad);
  const Vec3 size = hi - lo + Vec3::Constant(2.0 * pad);
  grid.nx = static_cast<int>(std::ceil(size.x() / grid.cell)) + 1;
  grid.ny = static_cast<int>(std::ceil(size.y() / grid.cell)) + 1;
  grid.nz = static_cast<int>(std::ceil(size.z() / grid.cell)) + 1;
  return grid;
}

std::vector<double> SampleBruteForce(const Points& vertices, const Triangles& triangles,
                                     const SdfGrid& grid) {
  std::vector<double> values(grid.size());
  size_t n = 0;
  for (int k = 0; k < grid.nz; ++k) {
    for (int j = 0; j < grid.ny; ++j) {
      for (int i = 0; i < grid.nx; ++i) {
        const Vec3 p = grid.Point(i, j, k);
        double best = std::numeric_limits<double>::infinity();
        for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
          best = std::min(best, SquaredDistanceToTriangle(p, vertices.row(triangles(t, 0)),
                                                          vertices.row(triangles(t, 1)),
                                                          vertices.row(triangles(t, 2))));
        }
        values[n++] = Signed(InsideByWinding(vertices, triangles, p), best);
      }
    }
  }
  return values;
}

std::vector<double> SampleWithHierarchy(const Points& vertices, const Triangles& triangles,
                                        const SdfGrid& grid, TriangleBvh::BoundScales scales,
                                        SamplingStats* stats) {
  const TriangleBvh bvh(vertices, triangles, scales);
  std::vector<double> values(grid.size());
  size_t n = 0;
  int64_t exact_signs = 0;
  for (int k = 0; k < grid.nz; ++k) {
    for (int j = 0; j < grid.ny; ++j) {
      for (int i = 0; i < grid.nx; ++i) {
        const Vec3 p = grid.Point(i, j, k);
        // |estimate - brute-force sum| <= error: clear of 2 pi by more than that, both sums
        // fall on the same side (the margin also covers the brute force's division by 4 pi)
        const TriangleBvh::SolidAngleEstimate omega = bvh.MeshSolidAngle(p);
        const double magnitude = std::abs(omega.value);
        bool inside;
        if (magnitude - omega.error > 2.0 * M_PI) {
          inside = true;
        } else if (magnitude + omega.error < 2.0 * M_PI) {
          inside = false;
        } else {
          inside = InsideByWinding(vertices, triangles, p);
          ++exact_signs;
        }
        values[n++] = Signed(inside, bvh.NearestSquaredDistance(p));
      }
    }
  }
  if (stats) stats->exact_signs = exact_signs;
  return values;
}

}  // namespace viscera::collision
