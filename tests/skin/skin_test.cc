#include "skin/skin.h"

#include <filesystem>
#include <limits>

#include <gtest/gtest.h>

#include "common/check.h"
#include "mesh_geometry.h"
#include "skeletons.h"

namespace viscera::skin {
namespace {

// The factory makes every skin by name; each binds once, builds a closed outward mesh from
// a snapshot, rebuilds the same mesh size from the next snapshot (buffers reused), and the
// mesh round-trips through OBJ.
TEST(SkinTest, EverySkinByNameBuildsAndExports) {
  SkinOptions options;
  options.radius = 0.0125;
  options.hybrid.focus = Vec3(0.05, 0.0, 0.0);
  const Points q = testing::FlatSpiral(60, 1.0, 0.05, 0.03);
  for (const char* name : {"parametric", "implicit", "convolution", "hybrid"}) {
    auto skin = MakeSkin(name, options);
    EXPECT_EQ(skin->name(), name);
    skin->Bind(60);
    Mesh mesh;
    skin->Build(q, &mesh);
    EXPECT_TRUE(CheckTopology(mesh).closed_oriented_manifold()) << name;
    EXPECT_EQ(testing::SelfIntersections(mesh), 0) << name;
    EXPECT_EQ(testing::BadVertexFans(mesh), 0) << name;
    EXPECT_GT(SignedVolume(mesh), 0.0) << name;
    EXPECT_EQ(skin->stats().triangles, mesh.num_triangles());
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
    const Vec3* before = mesh.positions.data();
    skin->Build(q, &mesh);
    EXPECT_EQ(mesh.positions.data(), before) << name << ": the rebuild reallocated";
    const std::string path =
        (std::filesystem::temp_directory_path() / (std::string("viscera_") + name + ".obj"))
            .string();
    WriteMesh(path, mesh);
    EXPECT_EQ(ReadObj(path).num_triangles(), mesh.num_triangles());
  }
}

TEST(SkinTest, RejectsBadSnapshotsAndOptions) {
  SkinOptions options;
  for (const char* name : {"parametric", "implicit", "convolution", "hybrid"}) {
    auto skin = MakeSkin(name, options);
    Mesh mesh;
    EXPECT_THROW(skin->Build(testing::Straight(10, 1.0), &mesh), InputError)
        << name << ": before Bind";
    skin->Bind(10);
    EXPECT_THROW(skin->Build(testing::Straight(12, 1.0), &mesh), InputError) << name;
    Points bad = testing::Straight(10, 1.0);
    bad(4, 1) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(skin->Build(bad, &mesh), InputError) << name;
  }
  options.radius = 0.0;
  EXPECT_THROW(MakeSkin("parametric", options), InputError);
  EXPECT_THROW(MakeSkin("marching", SkinOptions{}), InputError);
}

}  // namespace
}  // namespace viscera::skin
