#include "skin/mesh.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "mesh_geometry.h"

#include "common/check.h"

namespace viscera::skin {
namespace {

// A closed tetrahedron, outward orientation.
Mesh Tetrahedron() {
  Mesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

TEST(MeshTest, TetrahedronIsClosedOrientedWithVolumeOneSixth) {
  const Mesh m = Tetrahedron();
  const TopologyReport r = CheckTopology(m);
  EXPECT_TRUE(r.closed_oriented_manifold());
  EXPECT_EQ(r.components, 1);
  EXPECT_NEAR(SignedVolume(m), 1.0 / 6.0, 1e-15);
}

// The geometric checks see what indices cannot: two closed tetrahedra passing through each
// other, and two that touch at one vertex only (each closed and oriented).
TEST(MeshTest, GeometricChecksCatchCrossingsAndPinchedVertices) {
  const Mesh one = Tetrahedron();
  EXPECT_EQ(testing::SelfIntersections(one), 0);
  EXPECT_EQ(testing::BadVertexFans(one), 0);
  auto two = [&](const Vec3& offset, bool share_vertex) {
    Mesh m = Tetrahedron();
    const int base = m.num_vertices();
    for (int v = 0; v < 4; ++v) m.positions.push_back(Tetrahedron().positions[v] + offset);
    for (Eigen::Vector3i t : Tetrahedron().triangles) {
      for (int i = 0; i < 3; ++i)
        t[i] = share_vertex && t[i] == 0 ? 3 : t[i] + base;  // 2nd's corner 0 = 1st's 3
      m.triangles.push_back(t);
    }
    return m;
  };
  const Mesh crossing = two(Vec3(0.2, 0.2, 0.2), false);
  EXPECT_TRUE(CheckTopology(crossing).closed_oriented_manifold());
  EXPECT_GT(testing::SelfIntersections(crossing, /*neighbourhood=*/0), 0);
  EXPECT_EQ(testing::BadVertexFans(crossing), 0);
  const Mesh apart = two(Vec3(3, 0, 0), false);
  EXPECT_EQ(testing::SelfIntersections(apart, 0), 0);
  const Mesh pinched = two(Vec3(0, 0, 1), true);  // second tetrahedron stands on the first's apex
  EXPECT_EQ(testing::BadVertexFans(pinched), 1);
  EXPECT_EQ(testing::SelfIntersections(pinched, 0), 0);
}

TEST(MeshTest, TopologyCheckCatchesHolesFlipsAndFins) {
  Mesh hole = Tetrahedron();
  hole.triangles.pop_back();
  EXPECT_EQ(CheckTopology(hole).boundary_edges, 3);
  Mesh flipped = Tetrahedron();
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  EXPECT_EQ(CheckTopology(flipped).misoriented_edges, 3);
  Mesh fin = Tetrahedron();
  fin.positions.push_back(Vec3(-1, -1, 0));
  fin.triangles.emplace_back(0, 1, 4);
  EXPECT_EQ(CheckTopology(fin).nonmanifold_edges, 1);
}

TEST(MeshTest, ObjAndPlyRoundTrip) {
  Mesh m = Tetrahedron();
  ComputeVertexNormals(&m);
  const auto dir = std::filesystem::temp_directory_path();
  const std::string obj = (dir / "viscera_mesh_test.obj").string();
  WriteMesh(obj, m);
  const Mesh back = ReadObj(obj);
  ASSERT_EQ(back.num_vertices(), 4);
  ASSERT_EQ(back.num_triangles(), 4);
  for (int i = 0; i < 4; ++i) EXPECT_LT((back.positions[i] - m.positions[i]).norm(), 1e-6);
  EXPECT_EQ(back.triangles, m.triangles);
  const std::string ply = (dir / "viscera_mesh_test.ply").string();
  WriteMesh(ply, m);
  // header + 4 vertices * 6 floats + 4 faces * (1 + 12) bytes
  const auto size = std::filesystem::file_size(ply);
  EXPECT_GT(size, 4u * 24u + 4u * 13u);
  EXPECT_THROW(WriteMesh((dir / "mesh.stl").string(), m), InputError);
}

}  // namespace
}  // namespace viscera::skin
