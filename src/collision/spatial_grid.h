#pragma once
/// Broad phase: a uniform grid (spatial hash) with cells one sphere diameter wide, rebuilt every
/// step in O(n). Each sphere is checked against its own cell and the 26 around it, so no pair
/// closer than a cell width is missed across a cell boundary (the paper checked only the same
/// voxel). Pairs come out in a deterministic order.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/types.h"

namespace viscera::collision {

class SpatialGrid {
 public:
  /// @param cell cell width (m), at least the largest interaction distance.
  explicit SpatialGrid(double cell) : cell_(cell) {}
  void set_cell(double cell) { cell_ = cell; }

  /// Calls pair(i, j), i < j, exactly once for every pair of points closer than the cell width
  /// (and some farther ones: the caller checks distances). Allocates nothing once sized.
  template <typename PairFn>
  void ForEachCandidatePair(const std::vector<Vec3>& points, PairFn&& pair);

  /// Indexes `points` for ForEachNear. Allocates nothing once sized.
  void Index(const std::vector<Vec3>& points) { Build(points); }
  /// Calls near(j) once for every indexed point j in p's cell or the 26 around it: every point
  /// closer to p than the cell width, and some farther (the caller checks distances).
  template <typename NearFn>
  void ForEachNear(const Vec3& p, NearFn&& near) const;

  /// All pairs (i < j) of points closer than `distance`, brute force, O(n^2): the reference.
  static std::vector<std::pair<int, int>> BruteForcePairs(const std::vector<Vec3>& points,
                                                          double distance);

 private:
  void Build(const std::vector<Vec3>& points);
  uint64_t Key(int64_t x, int64_t y, int64_t z) const;
  int Find(uint64_t key) const;  // slot of key in the table, -1 if absent

  double cell_;
  std::vector<int64_t> coords_;     // 3 per point: integer cell coordinates
  std::vector<int> next_;           // next point in the same cell, -1 at the end
  std::vector<uint64_t> slot_key_;  // open-addressing table: cell key ...
  std::vector<int> slot_head_;      // ... -> first point of the cell (ascending order), -1 = empty
  uint64_t mask_ = 0;
};

template <typename PairFn>
void SpatialGrid::ForEachCandidatePair(const std::vector<Vec3>& points, PairFn&& pair) {
  Build(points);
  // Half of the 26 neighbour cells (those lexicographically after the cell) plus the cell
  // itself: every pair of adjacent cells is visited once, from one side.
  static constexpr int kHalf[13][3] = {{1, -1, -1}, {1, -1, 0}, {1, -1, 1}, {1, 0, -1}, {1, 0, 0},
                                       {1, 0, 1},   {1, 1, -1}, {1, 1, 0},  {1, 1, 1},  {0, 1, -1},
                                       {0, 1, 0},   {0, 1, 1},  {0, 0, 1}};
  const int n = static_cast<int>(points.size());
  for (int i = 0; i < n; ++i) {
    const int64_t cx = coords_[3 * i], cy = coords_[3 * i + 1], cz = coords_[3 * i + 2];
    for (int j = next_[i]; j >= 0; j = next_[j]) pair(i, j);  // same cell, j > i
    for (const auto& d : kHalf) {
      const int slot = Find(Key(cx + d[0], cy + d[1], cz + d[2]));
      if (slot < 0) continue;
      for (int j = slot_head_[slot]; j >= 0; j = next_[j]) pair(std::min(i, j), std::max(i, j));
    }
  }
}

template <typename NearFn>
void SpatialGrid::ForEachNear(const Vec3& p, NearFn&& near) const {
  int64_t c[3];
  for (int a = 0; a < 3; ++a) c[a] = static_cast<int64_t>(std::floor(p(a) / cell_));
  for (int dx = -1; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
        const int slot = Find(Key(c[0] + dx, c[1] + dy, c[2] + dz));
        if (slot < 0) continue;
        for (int j = slot_head_[slot]; j >= 0; j = next_[j]) near(j);
      }
    }
  }
}

}  // namespace viscera::collision
