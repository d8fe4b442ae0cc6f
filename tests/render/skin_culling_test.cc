// SkinCuller: the tube pieces in the view are always drawn, those wholly outside it are not,
// and the drawn ones come nearest first.
#include "render/skin_culling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <tuple>

#include "render/laparoscope.h"

namespace viscera::render {
namespace {

// A tube of `rings` rings of `sides` vertices along a wavy line across x in [-0.6, 0.6] m,
// triangles ring after ring as the ring-based skins emit them.
skin::Mesh WavyTube(int rings, int sides, double radius, double phase) {
  skin::Mesh mesh;
  for (int r = 0; r < rings; ++r) {
    const double s = static_cast<double>(r) / (rings - 1);
    const Vec3 c(-0.6 + 1.2 * s, 0.08 * std::sin(9.0 * s + phase), 0.05 * std::cos(7.0 * s));
    for (int k = 0; k < sides; ++k) {
      const double a = 2.0 * std::numbers::pi * k / sides;
      const Vec3 n(0.0, std::cos(a), std::sin(a));
      mesh.positions.push_back(c + radius * n);
      mesh.normals.push_back(n);
      mesh.surface.emplace_back(s, a);
    }
  }
  for (int r = 0; r + 1 < rings; ++r) {
    for (int k = 0; k < sides; ++k) {
      const int a = r * sides + k, b = r * sides + (k + 1) % sides;
      mesh.triangles.emplace_back(a, a + sides, b);
      mesh.triangles.emplace_back(b, a + sides, b + sides);
    }
  }
  return mesh;
}

using Triangle = std::tuple<float, float, float, float, float, float, float, float, float>;

Triangle Key(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c) {
  return {a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), c.x(), c.y(), c.z()};
}

// True when any point of the triangle (its vertices or the centroid) is inside the clip volume.
bool SeenPoint(const Eigen::Matrix4f& m, const Eigen::Vector3f& p) {
  const Eigen::Vector4f c = m * p.homogeneous();
  return c.w() > 0.0f && std::abs(c.x()) <= c.w() && std::abs(c.y()) <= c.w() &&
         std::abs(c.z()) <= c.w();
}

TEST(SkinCuller, KeepsEveryTriangleInTheViewAndLeavesOutChunksOutsideIt) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int kept_in_view = 0, left_out = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const skin::Mesh mesh = WavyTube(120, 16, 0.0125, 0.3 * trial);
    Laparoscope scope;
    scope.eye = {0.3f * u(random), -0.15f + 0.05f * u(random), 0.12f + 0.05f * u(random)};
    scope.target = {0.3f * u(random), 0.05f * u(random), 0.0f};
    const CameraMatrices camera = scope.Matrices(640, 480);
    const Eigen::Matrix4f m = camera.projection * camera.view;

    TriMesh out;
    SkinCuller culler(64);
    const CullCounts counts = culler.Append(mesh, 3.0, 0.0125, camera, &out);
    std::set<Triangle> drawn;
    for (size_t i = 0; i < out.indices.size(); i += 3) {
      drawn.insert(Key(out.positions[out.indices[i]], out.positions[out.indices[i + 1]],
                       out.positions[out.indices[i + 2]]));
    }
    EXPECT_EQ(static_cast<long>(drawn.size()), counts.triangles_drawn);
    EXPECT_EQ(counts.triangles, mesh.num_triangles());
    for (const Eigen::Vector3i& t : mesh.triangles) {
      const Eigen::Vector3f a = mesh.positions[t[0]].cast<float>(),
                            b = mesh.positions[t[1]].cast<float>(),
                            c = mesh.positions[t[2]].cast<float>();
      const bool seen =
          SeenPoint(m, a) || SeenPoint(m, b) || SeenPoint(m, c) || SeenPoint(m, (a + b + c) / 3.0f);
      const bool kept = drawn.count(Key(a, b, c)) == 1;
      if (seen) {
        EXPECT_TRUE(kept) << "trial " << trial << ": a triangle in the view was dropped";
        ++kept_in_view;
      }
      if (!kept) ++left_out;
    }
    // the texture space is AppendSkin's, the vertices used once each
    EXPECT_EQ(out.texture.size(), out.positions.size());
    EXPECT_LE(out.num_vertices(), mesh.num_vertices());
  }
  EXPECT_GT(kept_in_view, 1000);
  EXPECT_GT(left_out, 1000);  // the culling does cull
}

TEST(SkinCuller, EmitsTheNearestChunkFirst) {
  const skin::Mesh mesh = WavyTube(120, 16, 0.0125, 0.0);
  Laparoscope scope;
  scope.eye = {0.7f, 0.0f, 0.0f};  // looking down the tube from its +x end
  scope.target = {0.0f, 0.0f, 0.0f};
  scope.up = {0.0f, 0.0f, 1.0f};
  const CameraMatrices camera = scope.Matrices(640, 480);
  TriMesh out;
  SkinCuller culler(32);
  culler.Append(mesh, 3.0, 0.0125, camera, &out);
  ASSERT_GT(out.indices.size(), 600u);
  // the first triangles drawn are near the +x end, the last near the -x end
  EXPECT_GT(out.positions[out.indices.front()].x(), 0.5f);
  EXPECT_LT(out.positions[out.indices.back()].x(), -0.4f);
}

TEST(Frustum, BoxesAcrossOrInsideTheViewAreNotOutside) {
  Laparoscope scope;
  scope.eye = {0.0f, -0.3f, 0.0f};
  scope.target = {0.0f, 0.0f, 0.0f};
  scope.up = {0.0f, 0.0f, 1.0f};
  const CameraMatrices camera = scope.Matrices(640, 480);
  const Frustum frustum(camera.projection * camera.view);
  auto box = [](float x, float y, float z, float h) {
    return Eigen::AlignedBox3f(Eigen::Vector3f(x - h, y - h, z - h),
                               Eigen::Vector3f(x + h, y + h, z + h));
  };
  EXPECT_FALSE(frustum.Outside(box(0.0f, 0.0f, 0.0f, 0.01f)));  // at the look-at
  EXPECT_FALSE(frustum.Outside(box(0.0f, 0.0f, 0.0f, 5.0f)));   // around the whole view
  EXPECT_TRUE(frustum.Outside(box(0.0f, -0.5f, 0.0f, 0.05f)));  // behind the eye
  EXPECT_TRUE(frustum.Outside(box(1.0f, 0.0f, 0.0f, 0.05f)));   // far to the right
  EXPECT_TRUE(frustum.Outside(box(0.0f, 5.0f, 0.0f, 0.05f)));   // beyond the far plane
}

}  // namespace
}  // namespace viscera::render
