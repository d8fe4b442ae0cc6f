#pragma once
/// A closed triangle mesh (OBJ) turned into a signed distance field at load time: distances on a
/// regular grid around the mesh (point-triangle distance; sign from the generalized winding
/// number, robust to small holes; collision/sdf_sampling.h), trilinearly interpolated at query
/// time.
#include <string>
#include <vector>

#include "collision/sdf_sampling.h"
#include "common/types.h"

namespace viscera::collision {

class MeshSdf {
 public:
  /// Loads `path` (v and f lines; polygons are fanned into triangles), scales then translates
  /// it, and samples the field on a grid of `resolution` cells along the longest side, padded.
  /// @throws InputError for a missing or malformed file or an empty mesh.
  static MeshSdf FromObj(const std::string& path, double scale, const Vec3& offset,
                         int resolution = 40);

  /// Builds the field from triangles directly (#V by 3 vertices, #F by 3 indices).
  MeshSdf(const Points& vertices,
          const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& faces, int resolution);

  /// Signed distance (positive outside the solid) and outward normal (the field's gradient).
  /// Far outside the grid, the distance to the grid box is added.
  double Distance(const Vec3& p, Vec3* normal) const;
  /// The distance alone: one interpolation rather than seven (the broad phase's query).
  double Distance(const Vec3& p) const;

  int triangles() const { return static_cast<int>(faces_.rows()); }
  /// The mesh the field was built from, scaled and placed (#V by 3, m), for rendering.
  const Points& vertices() const { return vertices_; }
  /// Its triangles (#F by 3 indices into vertices()), as read (polygons fanned).
  const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& faces() const { return faces_; }
  /// The sampling grid and its signed distances (m), x fastest.
  const SdfGrid& grid() const { return grid_; }
  const std::vector<double>& samples() const { return values_; }

 private:
  double Sample(int i, int j, int k) const {
    return values_[(static_cast<size_t>(k) * grid_.ny + j) * grid_.nx + i];
  }
  double Interpolate(const Vec3& p) const;

  Points vertices_;
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> faces_;
  SdfGrid grid_;
  std::vector<double> values_;
};

}  // namespace viscera::collision
