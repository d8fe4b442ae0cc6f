#include "collision/spatial_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace viscera::collision {
namespace {

std::vector<std::pair<int, int>> GridPairs(const std::vector<Vec3>& points, double distance) {
  SpatialGrid grid(distance);
  std::vector<std::pair<int, int>> pairs;
  grid.ForEachCandidatePair(points, [&](int i, int j) {
    if ((points[i] - points[j]).norm() < distance) pairs.emplace_back(i, j);
  });
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

TEST(SpatialGrid, MatchesBruteForceOnRandomPoints) {
  std::mt19937 rng(42);
  for (double box : {0.05, 0.2, 1.0}) {
    std::uniform_real_distribution<double> uni(-box, box);
    std::vector<Vec3> points(600);
    for (Vec3& p : points) p = Vec3(uni(rng), uni(rng), uni(rng));
    const auto expected = SpatialGrid::BruteForcePairs(points, 0.025);
    EXPECT_EQ(GridPairs(points, 0.025), expected) << "box " << box;
    if (box == 0.05) {
      EXPECT_GT(expected.size(), 1000u);  // a dense case really was tested
    }
  }
}

TEST(SpatialGrid, MatchesBruteForceOnPackedLatticeAcrossCellBoundaries) {
  // Points on a lattice whose spacing is just under the cell width, offset so that neighbours
  // straddle cell boundaries (the paper's same-voxel test would miss most of these pairs).
  std::vector<Vec3> points;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      for (int k = 0; k < 6; ++k)
        points.emplace_back(0.0249 * i + 0.013, 0.0249 * j - 0.007, 0.0249 * k + 0.0001);
    }
  }
  const auto expected = SpatialGrid::BruteForcePairs(points, 0.025);
  EXPECT_EQ(GridPairs(points, 0.025), expected);
  EXPECT_GT(expected.size(), 1000u);
}

TEST(SpatialGrid, HandlesNegativeCoordinatesAndRepeatedBuilds) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-3.0, -2.9);
  SpatialGrid grid(0.02);
  for (int round = 0; round < 3; ++round) {
    std::vector<Vec3> points(200);
    for (Vec3& p : points) p = Vec3(uni(rng), uni(rng), uni(rng));
    std::vector<std::pair<int, int>> pairs;
    grid.ForEachCandidatePair(points, [&](int i, int j) {
      if ((points[i] - points[j]).norm() < 0.02) pairs.emplace_back(i, j);
    });
    std::sort(pairs.begin(), pairs.end());
    EXPECT_EQ(pairs, SpatialGrid::BruteForcePairs(points, 0.02));
  }
}

}  // namespace
}  // namespace viscera::collision
