// SkinDetail: a tube seen along its length keeps every ring and side near the scope and fewer
// far from it, and the mix of levels is still one closed surface (no cracks at the joints).
#include "render/skin_detail.h"

#include <gtest/gtest.h>

#include <cmath>

#include "render/laparoscope.h"
#include "skin/parametric_skin.h"

namespace viscera::render {
namespace {

constexpr double kRadius = 0.0125;

// A parametric skin (16 sides, 8 rings per segment, caps) of a gently wavy line along x from 0 to
// 0.6 m.
skin::Mesh WavyTube() {
  constexpr int kPoints = 25;
  Points q(kPoints, 3);
  for (int i = 0; i < kPoints; ++i) {
    const double x = 0.6 * i / (kPoints - 1);
    q.row(i) << x, 0.01 * std::sin(20.0 * x), 0.008 * std::cos(15.0 * x);
  }
  skin::ParametricOptions options;
  options.sides = 16;
  skin::ParametricSkin skin(kRadius, options);
  skin.Bind(kPoints);
  skin::Mesh mesh;
  skin.Build(q, &mesh);
  return mesh;
}

// The scope behind the tube's start, looking along it: the whole tube in view, its start 10 cm
// away and its end 70 cm.
CameraMatrices AlongTheTube() {
  Laparoscope scope;
  scope.eye = {-0.1f, 0.0f, 0.02f};
  scope.target = {0.3f, 0.0f, 0.0f};
  scope.up = {0.0f, 0.0f, 1.0f};
  return scope.Matrices(640, 480);
}

TEST(SkinDetail, KeepsTheNearRingsAndSidesAndCoarsensTheFarOnes) {
  const skin::Mesh mesh = WavyTube();
  ASSERT_EQ(mesh.tube.sides, 16);
  ASSERT_EQ(mesh.tube.rings, 24 * 8 + 1);
  TriMesh out;
  SkinDetail detail;
  const CullCounts counts = detail.Append(mesh, 0.6, kRadius, AlongTheTube(), 480, 1.0, &out);
  const std::vector<SkinDetail::Block>& blocks = detail.blocks();
  ASSERT_EQ(blocks.size(), 48u);
  for (const SkinDetail::Block& b : blocks) EXPECT_TRUE(b.drawn);
  // the nearest piece of tube: every ring and side, the skin's own triangles
  const SkinDetail::Block& near = blocks.front();
  EXPECT_EQ(near.level, 0);
  EXPECT_EQ(near.triangles, 2 * 16 * (near.last_ring - near.first_ring));
  // the far end: coarser, fewer triangles
  const SkinDetail::Block& far = blocks.back();
  EXPECT_GT(far.level, 0);
  EXPECT_LE(far.triangles, 16 * (far.last_ring - far.first_ring));
  // coarser and coarser away from the scope
  EXPECT_LE(blocks[10].level, blocks[40].level);
  EXPECT_EQ(counts.triangles, mesh.num_triangles());
  EXPECT_EQ(static_cast<long>(out.indices.size()), 3 * counts.triangles_drawn);
  EXPECT_LT(counts.triangles_drawn, mesh.num_triangles() * 3 / 4);

  // one closed, consistently oriented surface: each edge of the drawn triangles is shared by
  // exactly two of them, once each way (a vertex of one level left off the other would not be)
  skin::Mesh drawn;
  for (const Eigen::Vector3f& p : out.positions) drawn.positions.push_back(p.cast<double>());
  for (size_t i = 0; i < out.indices.size(); i += 3) {
    drawn.triangles.emplace_back(out.indices[i], out.indices[i + 1], out.indices[i + 2]);
  }
  const skin::TopologyReport topology = skin::CheckTopology(drawn);
  EXPECT_TRUE(topology.closed_oriented_manifold())
      << topology.boundary_edges << " boundary, " << topology.nonmanifold_edges << " non-manifold, "
      << topology.misoriented_edges << " misoriented edges";
  EXPECT_EQ(topology.components, 1);
  // it encloses nearly the full skin's volume (a ring of 8 sides holds 0.92 of the area of one
  // of 16)
  EXPECT_NEAR(skin::SignedVolume(drawn), skin::SignedVolume(mesh), 0.05 * skin::SignedVolume(mesh));
}

TEST(SkinDetail, AFinerToleranceKeepsMore) {
  const skin::Mesh mesh = WavyTube();
  TriMesh coarse, fine;
  SkinDetail detail;
  const long loose =
      detail.Append(mesh, 0.6, kRadius, AlongTheTube(), 480, 4.0, &coarse).triangles_drawn;
  const long tight =
      detail.Append(mesh, 0.6, kRadius, AlongTheTube(), 480, 0.05, &fine).triangles_drawn;
  EXPECT_LT(loose, tight);
  // at a twentieth of a pixel everything is at full detail
  EXPECT_EQ(tight, mesh.num_triangles());
}

}  // namespace
}  // namespace viscera::render
