#pragma once
/// Marching cubes (Lorensen & Cline 1987) restricted to a narrow band: the polygonizer starts
/// from seed cells near the surface and only walks from a cell to the neighbours across faces
/// that the surface crosses (continuation, as in Bloomenthal's polygonizer), so it visits the
/// cells the surface passes through and not a full grid.
///
/// The case table is generated, not typed in: on each cube face the crossing edges are
/// paired into segments (on a face with two diagonal inside corners, each inside corner is
/// cut off on its own), oriented so that the surface faces away from the inside, and linked
/// into loops that are fan-triangulated. Neighbouring cells see the same face and decide it
/// the same way, so the output is a closed, consistently oriented 2-manifold wherever the
/// walk does not hit its cell budget.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/types.h"
#include "skin/flat_hash.h"
#include "skin/mesh.h"

namespace viscera::skin {

/// Triangles of the 256 cube cases. Corner c has offset (c & 1, c >> 1 & 1, c >> 2 & 1);
/// edge e = 4 * axis + (index of the other two bits) joins corner EdgeCorners(e)[0] to
/// [1] = [0] + unit(axis). A corner is inside when its value exceeds the iso-value.
class MarchingCubesTable {
 public:
  MarchingCubesTable();
  /// Up to 12 edge triples (counter-clockwise seen from outside), -1 terminated.
  const std::array<int8_t, 37>& Case(int config) const { return cases_[config]; }
  static std::array<int, 2> EdgeCorners(int edge);

 private:
  std::array<std::array<int8_t, 37>, 256> cases_;
};

/// A scalar field, larger inside the surface.
class ScalarField {
 public:
  virtual ~ScalarField() = default;
  virtual double Value(const Vec3& p) const = 0;
};

class NarrowBandPolygonizer {
 public:
  /// Polygonizes {p : field(p) = iso} on the grid of cell size `cell` anchored at the world
  /// origin, walking from the cells that contain `seeds` (points near the surface). Writes
  /// positions and triangles (no normals) into *out. Stops after max_cells cells.
  /// @pre cell > 0.
  void Run(const ScalarField& field, double iso, double cell, const std::vector<Vec3>& seeds,
           int max_cells, Mesh* out);

  int cells_visited() const { return cells_visited_; }
  long long field_evaluations() const { return evaluations_; }
  bool hit_budget() const { return hit_budget_; }

 private:
  // Grid storage in bricks of 8^3 grid points, found through a hash map of brick keys with a
  // one-entry cache (the walk is spatially coherent): far fewer hash look-ups than one per
  // grid point. Bricks are pooled and reused from frame to frame.
  static constexpr int kBrickShift = 3;
  static constexpr int kBrickMask = (1 << kBrickShift) - 1;
  static constexpr int kBrickPoints = 1 << (3 * kBrickShift);
  struct Brick {
    double value[kBrickPoints];     // field at the grid point, NaN until evaluated
    int vertex[kBrickPoints][3];    // vertex on the edge from the point along +x, +y, +z, or -1
                                    // (valid once value is)
    uint8_t visited[kBrickPoints];  // the cell whose lowest corner is the point was queued
  };
  Brick* BrickAt(int bi, int bj, int bk);

  MarchingCubesTable table_;
  std::vector<std::unique_ptr<Brick>> bricks_;
  int bricks_used_ = 0;
  FlatHashMap<int> brick_index_;
  uint64_t last_key_ = 0;
  Brick* last_brick_ = nullptr;
  std::vector<std::array<int, 3>> queue_;
  int cells_visited_ = 0;
  long long evaluations_ = 0;
  bool hit_budget_ = false;
};

}  // namespace viscera::skin
