#include "skin/parametric_skin.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "common/check.h"
#include "mesh_geometry.h"
#include "skeletons.h"
#include "test_support.h"

namespace viscera::skin {
namespace {

constexpr double kR = 0.0125;  // tube radius (m)

// Facets of the tube strips whose normal points towards the skeleton (turned inside out).
int InvertedTubeFacets(const ParametricSkin& skin, const Mesh& mesh) {
  const TubeRays& rays = skin.rays();
  int inverted = 0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    if (rays.IsCap(t[0]) || rays.IsCap(t[1]) || rays.IsCap(t[2])) continue;
    const Vec3 n = (mesh.positions[t[1]] - mesh.positions[t[0]])
                       .cross(mesh.positions[t[2]] - mesh.positions[t[0]]);
    const Vec3 outward =
        rays.directions()[t[0]] + rays.directions()[t[1]] + rays.directions()[t[2]];
    if (n.dot(outward) <= 0.0) ++inverted;
  }
  return inverted;
}

TEST(ParametricSkinTest, RadiusProfileFollowsCosSquared) {
  EXPECT_DOUBLE_EQ(ParametricRadius(0.9, 1.1, 0.0), 1.1);
  EXPECT_NEAR(ParametricRadius(0.9, 1.1, 0.5), 0.9, 1e-15);
  EXPECT_NEAR(ParametricRadius(0.9, 1.1, 0.25), 1.0, 1e-15);
  EXPECT_DOUBLE_EQ(ParametricRadius(0.9, 1.1, 1.0), 1.1);
}

// Tolerance: ring vertices are placed analytically, so |p - c| = R(s) to 1e-12 R and lie
// in the normal plane to 1e-9; the distance to the whole curve stays in [Rmin - 1% R, Rmax]
// on a helix whose curvature radius (5 R) is well above Rmax.
TEST(ParametricSkinTest, EveryVertexAtTheIntendedRadius) {
  for (const Points& q : {testing::Straight(20, 0.5), testing::Helix(60, 5 * kR, 4 * kR, 2.0)}) {
    ParametricSkin skin(kR, ParametricOptions{});
    skin.Bind(static_cast<int>(q.rows()));
    Mesh mesh;
    skin.Build(q, &mesh);
    const TubeRays& rays = skin.rays();
    const spline::CatmullRom curve(static_cast<int>(q.rows()));
    const std::vector<Vec3> dense = testing::DenseCurve(q);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const int ring = rays.vertex_ring()[v];
      const double s = rays.ring_params()[ring];
      const double x = s * curve.num_segments();
      const double expected = ParametricRadius(0.9 * kR, 1.1 * kR, x - std::floor(x));
      EXPECT_NEAR((mesh.positions[v] - rays.origins()[v]).norm(), expected, 1e-12 * kR);
      if (rays.IsCap(v)) continue;
      EXPECT_NEAR((mesh.positions[v] - rays.origins()[v]).dot(curve.Tangent(q, s).normalized()),
                  0.0, 1e-9 * kR);
      const double d = testing::DistanceToPolyline(dense, mesh.positions[v]);
      EXPECT_GE(d, 0.89 * kR);
      EXPECT_LE(d, 1.1 * kR + 1e-9);
    }
  }
}

// Closed, outward, volume within 1% of the polygonal prism of mean squared radius
// E[R^2] = Rmin^2 + Rmin dR + 3/8 dR^2 plus two hemispheres of Rmax.
TEST(ParametricSkinTest, ClosedOutwardWithExpectedVolume) {
  const double length = 1.0;
  const Points q = testing::Straight(41, length);
  ParametricOptions options;
  options.sides = 32;
  options.cap_rings = 8;
  ParametricSkin skin(kR, options);
  skin.Bind(41);
  Mesh mesh;
  skin.Build(q, &mesh);
  const TopologyReport r = CheckTopology(mesh);
  EXPECT_TRUE(r.closed_oriented_manifold());
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(testing::SelfIntersections(mesh), 0);
  EXPECT_EQ(testing::BadVertexFans(mesh), 0);
  const double r_min = 0.9 * kR, dr = 0.2 * kR;
  const double mean_r2 = r_min * r_min + r_min * dr + 0.375 * dr * dr;
  const double polygon = 32.0 / (2.0 * std::numbers::pi) * std::sin(2.0 * std::numbers::pi / 32.0);
  const double r_max = 1.1 * kR;
  const double expected = polygon * (std::numbers::pi * mean_r2 * length +
                                     4.0 / 3.0 * std::numbers::pi * std::pow(r_max, 3));
  EXPECT_NEAR(SignedVolume(mesh), expected, 0.01 * expected);
}

// Rings fold over on the inner side of a bend when the skeleton's curvature radius drops
// below the ring radius (kappa R >= 1). Documented bound, checked on the spline's own
// curvature: no inverted facet while kappa Rmax < 0.95 everywhere; inverted facets for a
// half circle of radius 0.6 Rmax. Both frame rules.
TEST(ParametricSkinTest, NoSelfIntersectingRingsWhileKappaRmaxBelowOne) {
  const double r_max = 1.1 * kR;
  for (FrameRule rule : {FrameRule::kDoubleReflection, FrameRule::kProjection}) {
    ParametricOptions options;
    options.frame_rule = rule;
    options.radius_min_factor = 1.1;  // constant radius Rmax isolates the bend effect
    // (not 1.3 Rmax: the spline overshoots the arc's curvature where it meets the arms, kappa
    // Rmax reaches 1.2 there, so neither bound would apply and the case would check nothing)
    for (double factor : {2.0, 0.6}) {
      const Points q = testing::UBend(120, 10 * kR, factor * r_max);
      ParametricSkin skin(kR, options);
      skin.Bind(120);
      Mesh mesh;
      skin.Build(q, &mesh);
      const spline::CatmullRom curve(120);
      double kappa = 0.0;
      for (int i = 0; i <= 4000; ++i) kappa = std::max(kappa, curve.Curvature(q, i / 4000.0));
      const int inverted = InvertedTubeFacets(skin, mesh);
      if (kappa * r_max < 0.95) {
        EXPECT_EQ(inverted, 0) << "bend radius " << factor
                               << " Rmax, kappa Rmax = " << kappa * r_max;
      }
      if (factor < 1.0) {
        EXPECT_GT(inverted, 0) << "bend radius " << factor
                               << " Rmax, kappa Rmax = " << kappa * r_max;
      } else {
        EXPECT_LT(kappa * r_max, 0.95) << "the test skeleton should stay below the bound";
      }
    }
  }
}

// Beyond the bound, prevent_folds (off by default, as in the paper) shortens the inner rays:
// no ring crosses the next any more, where the paper's skin has hundreds of crossings.
TEST(ParametricSkinTest, PreventFoldsRemovesRingCrossings) {
  for (double factor : {1.0, 0.6, 0.4}) {
    const Points q = testing::UBend(60, 8 * kR, factor * kR);
    ParametricOptions options;
    ParametricSkin paper(kR, options);
    options.prevent_folds = true;
    ParametricSkin guarded(kR, options);
    paper.Bind(60);
    guarded.Bind(60);
    Mesh a, b;
    paper.Build(q, &a);
    guarded.Build(q, &b);
    EXPECT_GT(testing::BackwardRingSteps(paper.rays(), a), 0) << "bend radius " << factor << " R";
    EXPECT_EQ(testing::BackwardRingSteps(guarded.rays(), b), 0) << "bend radius " << factor << " R";
    EXPECT_TRUE(CheckTopology(b).closed_oriented_manifold());
    EXPECT_EQ(testing::BadVertexFans(b), 0);
  }
}

// By geometry, which the index-only topology check cannot see, on a right-angle bend (whose
// arms, unlike a U-bend's, never overlap): the paper's skin crosses itself once the bend is
// tighter than R (the negative control: the check can fail), and no skin does above R.
TEST(ParametricSkinTest, TheUnguardedSkinCrossesItselfInBendsTighterThanR) {
  for (double factor : {1.5, 0.6, 0.4}) {
    ParametricSkin paper(kR, ParametricOptions{});
    paper.Bind(60);
    Mesh a;
    paper.Build(testing::LBend(60, 6 * kR, factor * kR), &a);
    if (factor < 1.0) {
      EXPECT_GT(testing::SelfIntersections(a), 0) << "bend radius " << factor << " R";
    } else {
      EXPECT_EQ(testing::SelfIntersections(a), 0) << "bend radius " << factor << " R";
    }
  }
}

// KNOWN FAILURE (ctest WILL_FAIL, tests/CMakeLists.txt). Missing capability: a fold-free skin
// in bends tighter than R. The fold guard (prevent_folds) keeps the rings in order, so no ring
// crosses the next, but the creased inner side still crosses itself (hundreds of triangle
// pairs at 0.6 R and 0.4 R, beyond any 8-edge neighbourhood). docs/skins.md says so. When this
// starts passing, ctest reports a failure: remove WILL_FAIL then.
TEST(ParametricSkinKnownFailure, PreventFoldsRemovesSelfIntersections) {
  for (double factor : {1.5, 0.6, 0.4}) {
    ParametricOptions options;
    options.prevent_folds = true;
    ParametricSkin guarded(kR, options);
    EXPECT_EQ(testing::CrossingsOnABend(&guarded, testing::LBend(60, 6 * kR, factor * kR), factor),
              0);
  }
}

TEST(ParametricSkinTest, RejectsBadInput) {
  ParametricSkin skin(kR, ParametricOptions{});
  Mesh mesh;
  EXPECT_THROW(skin.Build(testing::Straight(10, 1.0), &mesh), InputError);
  skin.Bind(10);
  EXPECT_THROW(skin.Build(testing::Straight(11, 1.0), &mesh), InputError);
  EXPECT_THROW(skin.Bind(3), InputError);
  EXPECT_THROW(ParametricSkin(-1.0, ParametricOptions{}), InputError);
  EXPECT_THROW(MakeSkin("nurbs", SkinOptions{}), InputError);
}

}  // namespace
}  // namespace viscera::skin
