#include "skin/marching_cubes.h"

#include <cmath>
#include <map>

#include <gtest/gtest.h>

namespace viscera::skin {
namespace {

// A field with several blobs: polygonized on a coarse grid it must give closed, outward
// meshes, whatever cube cases (including the ambiguous ones) occur.
class Blobs final : public ScalarField {
 public:
  explicit Blobs(std::vector<Vec3> c) : centres_(std::move(c)) {}
  double Value(const Vec3& p) const override {
    double f = 0.0;
    for (const Vec3& c : centres_) f += 1.0 / (0.05 + (p - c).squaredNorm());
    return f;
  }

 private:
  std::vector<Vec3> centres_;
};

TEST(MarchingCubesTest, EveryCaseGivesClosedOrientedSurfaces) {
  // Two blobs close enough to produce saddles; coarse cells hit many cube cases.
  std::srand(7);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Vec3> c;
    for (int k = 0; k < 3; ++k) c.push_back(Vec3::Random());
    const Blobs field(c);
    NarrowBandPolygonizer mc;
    Mesh m;
    std::vector<Vec3> seeds;
    for (const Vec3& x : c) {
      for (double r = 0.0; r < 3.0; r += 0.05) seeds.push_back(x + Vec3(r, 0.0, 0.0));
    }
    mc.Run(field, 4.0, 0.13 + 0.01 * trial, seeds, 1000000, &m);
    ASSERT_FALSE(mc.hit_budget());
    ASSERT_GT(m.num_triangles(), 0);
    const TopologyReport r = CheckTopology(m);
    EXPECT_EQ(r.boundary_edges, 0) << "trial " << trial;
    EXPECT_EQ(r.nonmanifold_edges, 0) << "trial " << trial;
    EXPECT_EQ(r.misoriented_edges, 0) << "trial " << trial;
    EXPECT_GT(SignedVolume(m), 0.0) << "trial " << trial;
  }
}

TEST(MarchingCubesTest, SphereVolumeAndRadius) {
  const Blobs field({Vec3(0.01, 0.02, 0.03)});
  // 1 / (0.05 + d^2) = 2  <=>  d^2 = 0.45
  const double radius = std::sqrt(0.45);
  NarrowBandPolygonizer mc;
  Mesh m;
  mc.Run(field, 2.0, 0.05, {Vec3(radius, 0.0, 0.0)}, 1000000, &m);
  EXPECT_TRUE(CheckTopology(m).closed_oriented_manifold());
  for (const Vec3& p : m.positions)
    EXPECT_NEAR((p - Vec3(0.01, 0.02, 0.03)).norm(), radius, 0.01 * radius);
  const double exact = 4.0 / 3.0 * 3.141592653589793 * radius * radius * radius;
  EXPECT_NEAR(SignedVolume(m), exact, 0.01 * exact);
}

}  // namespace
}  // namespace viscera::skin

namespace viscera::skin {
namespace {

// Random inside/outside labels on the points of an 8^3 grid, outside on its border: every
// cube case, the ambiguous faces included, appears; the result must still be closed.
class RandomGrid final : public ScalarField {
 public:
  RandomGrid(double cell, unsigned seed) : cell_(cell), seed_(seed) {}
  double Value(const Vec3& p) const override {
    const int i = static_cast<int>(std::lround(p.x() / cell_)),
              j = static_cast<int>(std::lround(p.y() / cell_)),
              k = static_cast<int>(std::lround(p.z() / cell_));
    if (std::min({i, j, k}) <= 0 || std::max({i, j, k}) >= 8) return -1.0;
    unsigned h = seed_ ^ (i * 73856093u) ^ (j * 19349663u) ^ (k * 83492791u);
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return (h & 1023u) / 1023.0 - 0.5;
  }

 private:
  double cell_;
  unsigned seed_;
};

TEST(MarchingCubesTest, RandomLabelsGiveClosedOrientedManifolds) {
  const double cell = 0.1;
  std::vector<Vec3> seeds;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      for (int k = 0; k < 8; ++k) seeds.push_back(Vec3(i + 0.5, j + 0.5, k + 0.5) * cell);
  for (unsigned seed = 1; seed <= 30; ++seed) {
    NarrowBandPolygonizer mc;
    Mesh m;
    mc.Run(RandomGrid(cell, seed), 0.0, cell, seeds, 1000000, &m);
    const TopologyReport r = CheckTopology(m);
    EXPECT_TRUE(r.closed_oriented_manifold())
        << "seed " << seed << ": boundary " << r.boundary_edges << ", non-manifold "
        << r.nonmanifold_edges << ", misoriented " << r.misoriented_edges;
    EXPECT_GT(SignedVolume(m), 0.0);
  }
}

}  // namespace
}  // namespace viscera::skin

namespace viscera::skin {
namespace {

// Directed boundary edges of one cube case's triangles, as pairs of edge midpoints in the
// cube's local coordinates; also checks that the interior edges pair up with opposite
// directions.
std::vector<std::pair<Vec3, Vec3>> CaseBoundary(const MarchingCubesTable& table, int config,
                                                bool* interior_ok) {
  auto mid = [](int edge) {
    const std::array<int, 2> c = MarchingCubesTable::EdgeCorners(edge);
    return Vec3(0.5 * (Vec3((c[0] & 1), (c[0] >> 1) & 1, (c[0] >> 2) & 1) +
                       Vec3((c[1] & 1), (c[1] >> 1) & 1, (c[1] >> 2) & 1)));
  };
  std::map<std::pair<int, int>, int> directed;
  const std::array<int8_t, 37>& t = table.Case(config);
  for (int i = 0; t[i] >= 0; i += 3) {
    for (int k = 0; k < 3; ++k) ++directed[{t[i + k], t[i + (k + 1) % 3]}];
  }
  std::vector<std::pair<Vec3, Vec3>> boundary;
  *interior_ok = true;
  for (const auto& [edge, count] : directed) {
    if (count != 1) *interior_ok = false;
    const int reverse =
        directed.count({edge.second, edge.first}) ? directed.at({edge.second, edge.first}) : 0;
    if (reverse == 0) boundary.emplace_back(mid(edge.first), mid(edge.second));
    if (reverse > 1) *interior_ok = false;
  }
  return boundary;
}

// Exhaustive crack check of the generated table: for every case, every face and every case
// of the neighbouring cube that agrees with it on that face (256 x 3 x 16), the two cubes'
// patches meet along the same segments of the shared face, traversed in opposite directions;
// and every patch's boundary lies on the cube's faces.
TEST(MarchingCubesTest, GeneratedTableIsCrackFreeAcrossEveryFace) {
  const MarchingCubesTable table;
  auto on_face = [](const Vec3& p, int axis, double side) {
    return std::abs(p[axis] - side) < 1e-12;
  };
  for (int a = 0; a < 256; ++a) {
    bool ok = true;
    const auto boundary_a = CaseBoundary(table, a, &ok);
    ASSERT_TRUE(ok) << "case " << a << " has a non-manifold interior";
    for (const auto& [p, q] : boundary_a) {
      bool some_face = false;
      for (int axis = 0; axis < 3; ++axis) {
        for (double side : {0.0, 1.0})
          some_face |= on_face(p, axis, side) && on_face(q, axis, side);
      }
      EXPECT_TRUE(some_face) << "case " << a << ": boundary edge inside the cube";
    }
    for (int axis = 0; axis < 3; ++axis) {
      const int bit = 1 << axis;
      for (int b = 0; b < 256; ++b) {
        // b is the cube at +axis: its corners with the bit clear are a's corners with it set
        bool agrees = true;
        for (int c = 0; c < 8 && agrees; ++c) {
          if (c & bit) continue;
          agrees = (((b >> c) & 1) == ((a >> (c | bit)) & 1));
        }
        if (!agrees) continue;
        const auto boundary_b = CaseBoundary(table, b, &ok);
        std::vector<std::pair<Vec3, Vec3>> from_a, from_b;
        for (const auto& [p, q] : boundary_a) {
          if (on_face(p, axis, 1.0) && on_face(q, axis, 1.0)) from_a.emplace_back(p, q);
        }
        for (const auto& [p, q] : boundary_b) {
          if (on_face(p, axis, 0.0) && on_face(q, axis, 0.0)) {
            // in a's coordinates, reversed
            from_b.emplace_back(q + Vec3::Unit(axis), p + Vec3::Unit(axis));
          }
        }
        ASSERT_EQ(from_a.size(), from_b.size()) << "cases " << a << " / " << b << " axis " << axis;
        for (const auto& e : from_a) {
          bool found = false;
          for (const auto& f : from_b)
            found |= (e.first - f.first).norm() < 1e-12 && (e.second - f.second).norm() < 1e-12;
          EXPECT_TRUE(found) << "cases " << a << " / " << b << " axis " << axis;
        }
      }
    }
  }
}

}  // namespace
}  // namespace viscera::skin
