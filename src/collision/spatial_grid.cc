#include "collision/spatial_grid.h"

#include <cmath>

namespace viscera::collision {

uint64_t SpatialGrid::Key(int64_t x, int64_t y, int64_t z) const {
  // 21 bits per axis (cells of 2.5 cm: +-26 km), packed; then mixed for the hash table.
  constexpr uint64_t kMask = (1u << 21) - 1;
  return ((static_cast<uint64_t>(x) & kMask) << 42) | ((static_cast<uint64_t>(y) & kMask) << 21) |
         (static_cast<uint64_t>(z) & kMask);
}

namespace {
uint64_t Hash(uint64_t key) { return (key * 0x9E3779B97F4A7C15ull) >> 20; }
}  // namespace

int SpatialGrid::Find(uint64_t key) const {
  for (uint64_t slot = Hash(key) & mask_;; slot = (slot + 1) & mask_) {
    if (slot_head_[slot] < 0) return -1;
    if (slot_key_[slot] == key) return static_cast<int>(slot);
  }
}

void SpatialGrid::Build(const std::vector<Vec3>& points) {
  const int n = static_cast<int>(points.size());
  coords_.resize(3 * static_cast<size_t>(n));
  next_.resize(n);
  size_t capacity = 16;
  while (capacity < 2 * static_cast<size_t>(n)) capacity *= 2;
  slot_key_.resize(capacity);
  slot_head_.assign(capacity, -1);
  mask_ = capacity - 1;
  // Insert in descending index order, pushing at the front: each cell lists ascending indices.
  for (int i = n - 1; i >= 0; --i) {
    for (int a = 0; a < 3; ++a)
      coords_[3 * i + a] = static_cast<int64_t>(std::floor(points[i](a) / cell_));
    const uint64_t key = Key(coords_[3 * i], coords_[3 * i + 1], coords_[3 * i + 2]);
    uint64_t slot = Hash(key) & mask_;
    while (slot_head_[slot] >= 0 && slot_key_[slot] != key) slot = (slot + 1) & mask_;
    slot_key_[slot] = key;
    next_[i] = slot_head_[slot];
    slot_head_[slot] = i;
  }
}

std::vector<std::pair<int, int>> SpatialGrid::BruteForcePairs(const std::vector<Vec3>& points,
                                                              double distance) {
  std::vector<std::pair<int, int>> pairs;
  for (size_t i = 0; i < points.size(); ++i) {
    for (size_t j = i + 1; j < points.size(); ++j) {
      if ((points[i] - points[j]).norm() < distance)
        pairs.emplace_back(static_cast<int>(i), static_cast<int>(j));
    }
  }
  return pairs;
}

}  // namespace viscera::collision
