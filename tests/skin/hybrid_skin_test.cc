#include "skin/hybrid_skin.h"

#include <cmath>

#include <gtest/gtest.h>

#include "common/check.h"
#include "mesh_geometry.h"
#include "skeletons.h"
#include "skin/parametric_skin.h"

namespace viscera::skin {
namespace {

constexpr double kR = 0.0125;

HybridOptions Focus(const Vec3& c, double radius, double transition) {
  HybridOptions h;
  h.focus = c;
  h.focus_radius = radius;
  h.transition = transition;
  return h;
}

TEST(HybridSkinTest, FocusWeightIsSmoothStep) {
  EXPECT_EQ(FocusWeight(0.05, 0.1, 0.05), 1.0);
  EXPECT_EQ(FocusWeight(0.1, 0.1, 0.05), 1.0);
  EXPECT_NEAR(FocusWeight(0.15, 0.1, 0.05), 0.0, 1e-12);
  EXPECT_NEAR(FocusWeight(0.125, 0.1, 0.05), 0.5, 1e-12);
}

// No gap or crack at the seams: the whole hybrid mesh is one closed, consistently oriented
// 2-manifold; inside the focus every vertex is the convolution surface's (to 1e-12 m) and
// far from it the parametric radius R(s) (to 1e-12 m).
TEST(HybridSkinTest, ClosedWithoutCracksAndExactOutsideTheBand) {
  const Points q = testing::FlatSpiral(150, 2.0, 4 * kR, 2.4 * kR);
  const Vec3 focus = q.row(75).transpose();
  HybridSkin hybrid(kR, ParametricOptions{}, ConvolutionOptions{}, Focus(focus, 0.06, 0.04));
  hybrid.Bind(150);
  Mesh mesh;
  hybrid.Build(q, &mesh);
  const TopologyReport r = CheckTopology(mesh);
  EXPECT_TRUE(r.closed_oriented_manifold())
      << r.boundary_edges << " boundary, " << r.nonmanifold_edges << " non-manifold, "
      << r.misoriented_edges << " misoriented";
  EXPECT_EQ(r.components, 1);
  EXPECT_GT(SignedVolume(mesh), 0.0);
  EXPECT_EQ(testing::SelfIntersections(mesh), 0);  // where the two skins meet, too
  EXPECT_EQ(testing::BadVertexFans(mesh), 0);

  ConvolutionSkin convolution(kR, ConvolutionOptions{});
  convolution.Bind(150);
  Mesh reference;
  convolution.Build(q, &reference);
  ASSERT_EQ(reference.num_vertices(), mesh.num_vertices());
  const std::vector<double>& w = hybrid.vertex_weights();
  int inside = 0, outside = 0, band = 0;
  const spline::CatmullRom curve(150);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (w[v] == 1.0) {
      ++inside;
      // the same seeds solved from a different start: equal to a few solver tolerances
      EXPECT_LT((mesh.positions[v] - reference.positions[v]).norm(), 3e-4 * kR);
    } else if (w[v] == 0.0) {
      ++outside;
      // same rays as the reference convolution skin (same frames and adaptive rings)
      const TubeRays& rays = convolution.rays();
      const double x = rays.ring_params()[rays.vertex_ring()[v]] * curve.num_segments();
      const double expected = ParametricRadius(0.9 * kR, 1.1 * kR, x - std::floor(x));
      EXPECT_NEAR((mesh.positions[v] - rays.origins()[v]).norm(), expected, 1e-12);
    } else {
      ++band;
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 100);
  EXPECT_GT(band, 100);
}

// No popping: moving the focus by 1 mm moves no vertex by more than the smoothstep slope
// (1.5 / transition) times 1 mm times the largest parametric / convolution radius gap
// (0.25 R here), plus the solver tolerance. A hard switch (transition 0) does pop.
TEST(HybridSkinTest, MovingFocusDoesNotPop) {
  const Points q = testing::FlatSpiral(150, 2.0, 4 * kR, 2.4 * kR);
  const Vec3 focus = q.row(75).transpose();
  const double step = 0.001, transition = 0.04;
  auto max_move = [&](double band) {
    HybridSkin hybrid(kR, ParametricOptions{}, ConvolutionOptions{}, Focus(focus, 0.06, band));
    hybrid.Bind(150);
    Mesh a, b;
    hybrid.Build(q, &a);
    hybrid.SetFocus(focus + Vec3(step, 0.0, 0.0), 0.06);
    hybrid.Build(q, &b);
    double worst = 0.0;
    for (int v = 0; v < a.num_vertices(); ++v)
      worst = std::max(worst, (a.positions[v] - b.positions[v]).norm());
    return worst;
  };
  const double bound = 1.5 / transition * step * 0.25 * kR + 3e-4 * kR;
  const double smooth = max_move(transition);
  const double hard = max_move(1e-9);
  std::printf(
      "max vertex move for a 1 mm focus move: smooth %.2e m (bound %.2e), hard switch %.2e m\n",
      smooth, bound, hard);
  EXPECT_LT(smooth, bound);
  EXPECT_GT(hard, 5.0 * bound);
}

TEST(HybridSkinTest, RejectsBadFocus) {
  HybridSkin hybrid(kR, ParametricOptions{}, ConvolutionOptions{}, HybridOptions{});
  EXPECT_THROW(hybrid.SetFocus(Vec3::Zero(), 0.0), InputError);
  EXPECT_NO_THROW(MakeSkin("hybrid", SkinOptions{}));
}

}  // namespace
}  // namespace viscera::skin
