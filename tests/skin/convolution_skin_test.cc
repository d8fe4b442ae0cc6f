#include "skin/convolution_skin.h"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "common/check.h"
#include "mesh_geometry.h"
#include "skeletons.h"
#include "test_support.h"

namespace viscera::skin {
namespace {

constexpr double kR = 0.0125;  // tube radius (m)

struct RadiusError {
  double max_tube = 0.0;                // max |d - R| / R over tube (non-cap) vertices
  double cap_min = 1e9, cap_max = 0.0;  // cap vertices' distance to the curve / R
};

RadiusError MeasureRadius(const ConvolutionSkin& skin, const Mesh& mesh, const Points& q) {
  const std::vector<Vec3> dense = testing::DenseCurve(q);
  RadiusError e;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double d = testing::DistanceToPolyline(dense, mesh.positions[v]) / kR;
    if (skin.rays().IsCap(v)) {
      e.cap_min = std::min(e.cap_min, d);
      e.cap_max = std::max(e.cap_max, d);
    } else {
      e.max_tube = std::max(e.max_tube, std::abs(d - 1.0));
    }
  }
  return e;
}

Mesh BuildOnce(ConvolutionSkin* skin, const Points& q) {
  skin->Bind(static_cast<int>(q.rows()));
  Mesh mesh;
  skin->Build(q, &mesh);
  return mesh;
}

// Tolerances: on a straight tube the iso-value calibration is exact, so the error is the
// solver's (1e-4 R) plus the polyline skeleton (< 1e-6 R): 2e-4 R. On a helix of curvature
// radius 6 R and on the packed spiral (turns 2.4 R apart, innermost curvature radius 4 R),
// the bent local skeleton (sagitta (D / 2)^2 kappa / 2 = 0.1 R at kappa = 1 / 4R) moves the
// surface: measured 1.9% and 2.9% R; tolerance 4% R.
// Cap vertices lie between 0.7 R and R from the end point (flattened cap of a finite window).
TEST(ConvolutionSkinTest, EveryVertexAtTheIntendedRadius) {
  {
    const Points q = testing::Straight(30, 0.6);
    ConvolutionSkin skin(kR, ConvolutionOptions{});
    const Mesh mesh = BuildOnce(&skin, q);
    const RadiusError e = MeasureRadius(skin, mesh, q);
    EXPECT_LT(e.max_tube, 2e-4);
    EXPECT_GT(e.cap_min, 0.7);
    EXPECT_LT(e.cap_max, 1.0 + 2e-4);
  }
  for (const Points& q :
       {testing::Helix(80, 6 * kR, 4 * kR, 2.0), testing::FlatSpiral(120, 1.5, 4 * kR, 2.4 * kR)}) {
    ConvolutionSkin skin(kR, ConvolutionOptions{});
    const Mesh mesh = BuildOnce(&skin, q);
    const RadiusError e = MeasureRadius(skin, mesh, q);
    RecordProperty("max_tube_error", std::to_string(e.max_tube));
    std::printf("max |d - R| / R = %.4f, caps in [%.3f, %.3f] R\n", e.max_tube, e.cap_min,
                e.cap_max);
    EXPECT_LT(e.max_tube, 0.04);
    EXPECT_GT(e.cap_min, 0.7);
    EXPECT_LT(e.cap_max, 1.03);
  }
}

// Closed 2-manifold, outward, and volume: polygonal tube pi R^2 L (sides factor) plus two
// caps taken as half ellipsoids of semi-axes (R, h), h the pole's distance: within 1%.
TEST(ConvolutionSkinTest, ClosedOutwardManifoldWithVolumePiR2L) {
  const double length = 0.8;
  const Points q = testing::Straight(40, length);
  ConvolutionSkin skin(kR, ConvolutionOptions{});
  const Mesh mesh = BuildOnce(&skin, q);
  const TopologyReport r = CheckTopology(mesh);
  EXPECT_TRUE(r.closed_oriented_manifold());
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(testing::SelfIntersections(mesh), 0);
  EXPECT_EQ(testing::BadVertexFans(mesh), 0);
  const int m = ConvolutionOptions{}.sides;
  const double polygon = m / (2.0 * std::numbers::pi) * std::sin(2.0 * std::numbers::pi / m);
  const double h = -mesh.positions[0].x();  // front pole, the tube starts at x = 0
  const double expected = polygon * std::numbers::pi * kR * kR * (length + 4.0 / 3.0 * h);
  EXPECT_NEAR(SignedVolume(mesh), expected, 0.01 * expected);
  // and on a bent, packed configuration the volume stays within 2% of pi R^2 L
  const Points spiral = testing::FlatSpiral(150, 2.0, 4 * kR, 2.4 * kR);
  ConvolutionSkin bent(kR, ConvolutionOptions{});
  const Mesh bent_mesh = BuildOnce(&bent, spiral);
  EXPECT_TRUE(CheckTopology(bent_mesh).closed_oriented_manifold());
  EXPECT_EQ(testing::SelfIntersections(bent_mesh), 0);  // the packed turns do not touch
  EXPECT_EQ(testing::BadVertexFans(bent_mesh), 0);
  const double spiral_length = spline::CatmullRom(150).Length(spiral);
  const double bent_expected =
      polygon * std::numbers::pi * kR * kR * (spiral_length + 4.0 / 3.0 * h);
  EXPECT_NEAR(SignedVolume(bent_mesh), bent_expected, 0.02 * bent_expected);
}

// Vertices of the middle of the arms of a hairpin: distance to their own arm's axis (the
// lines y = -gap/2 and y = +gap/2).
// A vertex belongs to the arm its ray starts from (it may lie inside the other arm).
double MaxArmRadiusError(const ConvolutionSkin& skin, const Mesh& mesh, double arm, double gap,
                         double* min_abs_y) {
  double worst = 0.0;
  *min_abs_y = 1e9;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    if (p.x() < 3 * kR || p.x() > arm - 3 * kR) continue;
    const double axis_y = skin.rays().origins()[v].y() < 0.0 ? -0.5 * gap : 0.5 * gap;
    const double d = std::hypot(p.y() - axis_y, p.z());
    worst = std::max(worst, std::abs(d / kR - 1.0));
    *min_abs_y = std::min(*min_abs_y, std::abs(p.y()));
  }
  return worst;
}

// Two non-consecutive parts closer than 2R (axes 1.6 R apart, they interpenetrate) keep
// their own round sections: every arm vertex within 2e-4 R of R from its own axis. With the
// whole skeleton convolved (local = false) the same test fails: the arms bulge (> 5% R).
// Axes 2.2 R apart: the 0.2 R gap stays open (no vertex within 0.05 R of the mid-plane),
// and again global convolution fails the radius test.
TEST(ConvolutionSkinTest, NonConsecutivePartsDoNotBlend) {
  const double arm = 30 * kR;
  double min_abs_y = 0.0;
  {
    const Points q = testing::Hairpin(120, arm, 1.6 * kR);
    ConvolutionSkin local(kR, ConvolutionOptions{});
    const Mesh mesh = BuildOnce(&local, q);
    EXPECT_LT(MaxArmRadiusError(local, mesh, arm, 1.6 * kR, &min_abs_y), 2e-4);
    ConvolutionOptions global_options;
    global_options.local = false;
    ConvolutionSkin global(kR, global_options);
    const Mesh blended = BuildOnce(&global, q);
    EXPECT_GT(MaxArmRadiusError(global, blended, arm, 1.6 * kR, &min_abs_y), 0.05);
  }
  {
    const Points q = testing::Hairpin(120, arm, 2.2 * kR);
    ConvolutionSkin local(kR, ConvolutionOptions{});
    const Mesh mesh = BuildOnce(&local, q);
    EXPECT_LT(MaxArmRadiusError(local, mesh, arm, 2.2 * kR, &min_abs_y), 2e-4);
    EXPECT_GT(min_abs_y, 0.05 * kR);
    ConvolutionOptions global_options;
    global_options.local = false;
    ConvolutionSkin global(kR, global_options);
    const Mesh blended = BuildOnce(&global, q);
    EXPECT_GT(MaxArmRadiusError(global, blended, arm, 2.2 * kR, &min_abs_y), 0.05);
  }
}

// Seeds that start from their previous positions reach the surface in fewer field
// evaluations than seeds starting from the skeleton, on a skeleton that moved by up to
// 0.05 R per control point between frames (fixed seed), and end on the same surface (the
// two meshes agree to 3 solver tolerances).
TEST(ConvolutionSkinTest, WarmStartBeatsColdStart) {
  Points q = testing::FlatSpiral(120, 1.5, 4 * kR, 2.4 * kR);
  ConvolutionSkin skin(kR, ConvolutionOptions{});
  Mesh first = BuildOnce(&skin, q);
  const long long cold_first = skin.stats().field_evaluations;
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> jitter(-0.05 * kR, 0.05 * kR);
  for (int i = 0; i < q.rows(); ++i)
    q.row(i) += Eigen::RowVector3d(jitter(rng), jitter(rng), jitter(rng));
  Mesh warm_mesh, cold_mesh;
  skin.Build(q, &warm_mesh);
  const long long warm = skin.stats().field_evaluations;
  skin.ResetWarmStart();
  skin.Build(q, &cold_mesh);
  const long long cold = skin.stats().field_evaluations;
  const double vertices = warm_mesh.num_vertices();
  std::printf("evaluations per seed: cold %.2f (first frame %.2f), warm %.2f\n", cold / vertices,
              cold_first / static_cast<double>(first.num_vertices()), warm / vertices);
  EXPECT_LT(warm, cold);
  EXPECT_LT(warm / vertices, 0.6 * cold / vertices);
  ASSERT_EQ(warm_mesh.num_vertices(), cold_mesh.num_vertices());
  double worst = 0.0;
  for (int v = 0; v < warm_mesh.num_vertices(); ++v) {
    worst = std::max(worst, (warm_mesh.positions[v] - cold_mesh.positions[v]).norm());
  }
  EXPECT_LT(worst, 3 * ConvolutionOptions{}.tolerance * kR);
}

// Adaptive subdivision: rings are denser in the bend of a U than along its arms, and no
// outer-side edge is longer than the target (2 pi R / sides) by more than 10%.
TEST(ConvolutionSkinTest, AdaptiveSubdivisionRefinesBends) {
  const Points q = testing::UBend(80, 20 * kR, 2 * kR);
  ConvolutionSkin skin(kR, ConvolutionOptions{});
  const Mesh mesh = BuildOnce(&skin, q);
  const TubeRays& rays = skin.rays();
  double arm_step = 0.0, bend_step = 1e9;
  for (int i = 0; i + 1 < rays.num_rings(); ++i) {
    const Vec3 c = rays.ring_centers()[i];
    const double step = (rays.ring_centers()[i + 1] - c).norm();
    if (c.x() > 5 * kR) arm_step = std::max(arm_step, step);
    if (c.x() < -kR) bend_step = std::min(bend_step, step);
  }
  EXPECT_LT(bend_step, 0.75 * arm_step);
  const double target = 2.0 * std::numbers::pi * kR / ConvolutionOptions{}.sides;
  double longest = 0.0;
  for (int i = 0; i + 1 < rays.num_rings(); ++i) {
    for (int j = 0; j < rays.sides(); ++j) {
      longest = std::max(longest, (mesh.positions[rays.TubeVertex(i + 1, j)] -
                                   mesh.positions[rays.TubeVertex(i, j)])
                                      .norm());
    }
  }
  EXPECT_LT(longest, 1.1 * target);
}

TEST(ConvolutionSkinTest, RejectsNeighbourhoodOfTwoRadiiOrMore) {
  ConvolutionOptions options;
  options.neighbourhood_factor = 2.0;
  EXPECT_THROW(ConvolutionSkin(kR, options), InputError);
  ConvolutionSkin skin(kR, ConvolutionOptions{});
  Mesh mesh;
  EXPECT_THROW(skin.Build(testing::Straight(10, 1.0), &mesh), InputError);
}

}  // namespace
}  // namespace viscera::skin

namespace viscera::skin {
namespace {

// A coil whose turns touch: helix of radius 5 R and pitch 1.8 R, so neighbouring turns (not
// consecutive along the tube: one turn = 31 R of arc apart) are closer than 2 R. Every tube
// vertex stays within 3% R of R from its own ring centre (the helix's curvature alone moves
// the surface by ~2%); with the whole skeleton convolved the turns blend (> 10% R).
TEST(ConvolutionSkinTest, CoilWithTouchingTurnsKeepsRoundSections) {
  const double r = 0.0125;
  const Points q = testing::Helix(120, 5 * r, 1.8 * r, 3.0);
  auto worst_ring_error = [&](bool local) {
    ConvolutionOptions options;
    options.local = local;
    ConvolutionSkin skin(r, options);
    skin.Bind(120);
    Mesh mesh;
    skin.Build(q, &mesh);
    double worst = 0.0;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (skin.rays().IsCap(v)) continue;
      worst = std::max(worst,
                       std::abs((mesh.positions[v] - skin.rays().origins()[v]).norm() / r - 1.0));
    }
    return worst;
  };
  const double local = worst_ring_error(true), global = worst_ring_error(false);
  std::printf("coil: max |r - R| / R local %.4f, global %.4f\n", local, global);
  EXPECT_LT(local, 0.03);
  EXPECT_GT(global, 0.10);
}

}  // namespace
}  // namespace viscera::skin

namespace viscera::skin {
namespace {

// Rays can fold on the inner side of a bend tighter than the radius, like the parametric
// rings (and the convolution surface bulges there, up to 1.3 R at a bend radius of 0.5 R).
// With prevent_folds (default) no ring crosses the next in U-bends of radius R to 0.4 R; with
// it off they do. The mesh stays closed and oriented either way, so the index-only topology
// check cannot tell them apart (the geometric check below can).
TEST(ConvolutionSkinTest, TightBendsDoNotFoldRings) {
  const double r = 0.0125;
  for (double factor : {1.0, 0.5, 0.4}) {
    const Points q = testing::UBend(60, 8 * r, factor * r);
    ConvolutionSkin guarded(r, ConvolutionOptions{});
    ConvolutionOptions off;
    off.prevent_folds = false;
    ConvolutionSkin unguarded(r, off);
    guarded.Bind(60);
    unguarded.Bind(60);
    Mesh a, b;
    guarded.Build(q, &a);
    unguarded.Build(q, &b);
    EXPECT_EQ(testing::BackwardRingSteps(guarded.rays(), a), 0) << "bend radius " << factor << " R";
    EXPECT_GT(testing::BackwardRingSteps(unguarded.rays(), b), 0)
        << "bend radius " << factor << " R";
    EXPECT_TRUE(CheckTopology(a).closed_oriented_manifold());
    EXPECT_EQ(testing::BadVertexFans(a), 0);
  }
}

// By geometry, on a right-angle bend (a U-bend's arms overlap when its radius is below R, so
// any skin of it crosses): unguarded, triangles cross once the bend is tighter than R (the
// negative control); above R, neither skin crosses.
TEST(ConvolutionSkinTest, TheUnguardedSkinCrossesItselfInBendsTighterThanR) {
  const double r = 0.0125;
  for (double factor : {1.5, 0.5, 0.4}) {
    ConvolutionOptions off;
    off.prevent_folds = false;
    ConvolutionSkin unguarded(r, off), guarded(r, ConvolutionOptions{});
    unguarded.Bind(60);
    guarded.Bind(60);
    Mesh a, b;
    guarded.Build(testing::LBend(60, 6 * r, factor * r), &a);
    unguarded.Build(testing::LBend(60, 6 * r, factor * r), &b);
    if (factor < 1.0) {
      EXPECT_GT(testing::SelfIntersections(b), 0) << "bend radius " << factor << " R";
    } else {
      EXPECT_EQ(testing::SelfIntersections(a), 0) << "bend radius " << factor << " R";
      EXPECT_EQ(testing::SelfIntersections(b), 0) << "bend radius " << factor << " R";
    }
  }
}

// KNOWN FAILURE (ctest WILL_FAIL, tests/CMakeLists.txt). Missing capability: a fold-free skin
// in bends tighter than R. The fold guard keeps ring order but the creased inner side still
// crosses itself (docs/skins.md). When this starts passing, remove WILL_FAIL.
TEST(ConvolutionSkinKnownFailure, TightBendsDoNotCrossThemselves) {
  const double r = 0.0125;
  for (double factor : {0.5, 0.4}) {
    ConvolutionSkin guarded(r, ConvolutionOptions{});
    EXPECT_EQ(testing::CrossingsOnABend(&guarded, testing::LBend(60, 6 * r, factor * r), factor),
              0);
  }
}

}  // namespace
}  // namespace viscera::skin
