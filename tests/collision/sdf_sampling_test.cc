// The hierarchical distance-field build (SampleWithHierarchy, what MeshSdf uses) against the
// brute force it replaced, bit for bit, on the cavity's liver and on meshes chosen for the hard
// cases: grid points exactly on a cube's faces (winding number exactly 1/2, zero distance: its
// sign bit too), a slab thinner than a cell, an open wavy sheet (winding number crossing 1/2
// everywhere near it), a torus (not convex), degenerate triangles. Negative controls: a
// distance bound or a remainder bound that is wrong changes the field, so these tests would
// catch it.
#include "collision/sdf_sampling.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <memory>

#include "collision/mesh_sdf.h"
#include "common/check.h"
#include "scene/scene.h"
#include "tests/collision/test_meshes.h"

namespace viscera::collision {
namespace {

struct Comparison {
  int differ = 0;     // samples whose bits differ
  int sign_only = 0;  // of those, the same magnitude with the other sign
  int farther = 0;    // of those, a larger magnitude than the brute force's
  std::string first;  // the first difference, for the failure message
};

Comparison Compare(const std::vector<double>& brute, const std::vector<double>& fast) {
  Comparison c;
  EXPECT_EQ(brute.size(), fast.size());
  for (size_t n = 0; n < std::min(brute.size(), fast.size()); ++n) {
    if (std::bit_cast<uint64_t>(brute[n]) == std::bit_cast<uint64_t>(fast[n])) continue;
    if (c.differ++ == 0)
      c.first = Cat("sample ", n, ": brute force ", brute[n], ", hierarchy ", fast[n]);
    if (std::abs(brute[n]) == std::abs(fast[n])) ++c.sign_only;
    if (std::abs(fast[n]) > std::abs(brute[n])) ++c.farther;
  }
  return c;
}

struct Case {
  std::string name;
  test::Mesh mesh;
  int resolution;
};

std::vector<Case> Cases() {
  test::Mesh degenerate = test::Box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  // a triangle with no area and a sliver, on the cube's top face
  degenerate.vertices.conservativeResize(10, 3);
  degenerate.vertices.row(8) << 0.5, 0.5, 1.0;
  degenerate.vertices.row(9) << 0.5, 0.5 + 1e-9, 1.0;
  degenerate.triangles.conservativeResize(14, 3);
  degenerate.triangles.row(12) << 4, 8, 8;
  degenerate.triangles.row(13) << 4, 8, 9;
  return {
      {"cube", test::Box(Vec3(0, 0, 0), Vec3(1, 1, 1)), 8},  // cell 1/8: grid points on the faces
      {"slab", test::Box(Vec3(0, 0, 0), Vec3(1, 1, 0.02)), 8},
      {"sheet", test::WavySheet(), 24},
      {"torus", test::Torus(), 24},
      {"degenerate", degenerate, 8},
  };
}

TEST(SdfSampling, TheHierarchyGivesTheBruteForceSamplesBitForBit) {
  for (const Case& c : Cases()) {
    const SdfGrid grid = GridAround(c.mesh.vertices, c.resolution);
    SamplingStats stats;
    const Comparison diff =
        Compare(SampleBruteForce(c.mesh.vertices, c.mesh.triangles, grid),
                SampleWithHierarchy(c.mesh.vertices, c.mesh.triangles, grid, {}, &stats));
    EXPECT_EQ(diff.differ, 0) << c.name << ": " << diff.first;
    // on the cube's faces, the sheet and the degenerate cube, some sign needs the exact sum
    if (c.name != "slab" && c.name != "torus") {
      EXPECT_GT(stats.exact_signs, 0) << c.name;
    }
  }
}

TEST(SdfSampling, TheCubesFacesHoldZerosOfBothSigns) {
  // The hard case is really there: grid points exactly on the surface, whose -0.0 or +0.0
  // comes from the rounding of a winding number of exactly 1/2.
  const test::Mesh cube = test::Box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const std::vector<double> brute =
      SampleBruteForce(cube.vertices, cube.triangles, GridAround(cube.vertices, 8));
  int positive = 0, negative = 0;
  for (const double v : brute) {
    if (v == 0.0) (std::signbit(v) ? negative : positive)++;
  }
  EXPECT_GT(positive, 0);
  EXPECT_GT(negative, 0);
}

// scenes/cavity.toml's liver as the scene loads it (its file, scale, offset and resolution).
std::shared_ptr<const MeshSdf> CavityLiver() {
  const scene::Scene cavity = scene::LoadSceneFile(VISCERA_SOURCE_DIR "/scenes/cavity.toml");
  for (const Obstacle& o : cavity.model.obstacles) {
    if (o.name == "liver" && o.sdf) return o.sdf;
  }
  Fail("scenes/cavity.toml has no mesh obstacle named liver");
}

TEST(SdfSampling, TheLiverOfTheCavityIsBuiltBitForBit) {
  const std::shared_ptr<const MeshSdf> cavity_liver = CavityLiver();
  const MeshSdf& liver = *cavity_liver;
  const Comparison diff =
      Compare(SampleBruteForce(liver.vertices(), liver.faces(), liver.grid()), liver.samples());
  EXPECT_EQ(diff.differ, 0) << diff.first;
  EXPECT_EQ(liver.samples().size(), liver.grid().size());
}

TEST(SdfSampling, AWrongDistanceBoundChangesTheField) {
  // Negative control: claiming the subtrees' boxes are 1.5 times farther than they are prunes
  // triangles that are nearest; the comparison sees it, and only ever as larger distances.
  const std::shared_ptr<const MeshSdf> cavity_liver = CavityLiver();
  const MeshSdf& liver = *cavity_liver;
  const std::vector<double> brute = SampleBruteForce(liver.vertices(), liver.faces(), liver.grid());
  const Comparison diff = Compare(
      brute, SampleWithHierarchy(liver.vertices(), liver.faces(), liver.grid(), {1.5, 1.0}));
  EXPECT_GT(diff.differ, 0);
  EXPECT_EQ(diff.farther, diff.differ);
}

TEST(SdfSampling, AWrongRemainderBoundChangesTheField) {
  // Negative control: a remainder bound 10^4 times too small (the size that triangle_bvh_test's
  // control shows exceeded) accepts near subtrees' multipoles and trusts them near the
  // threshold: on the open sheet, whose winding number is near 1/2 all along it, signs flip
  // while magnitudes stay. (A closed mesh's winding number is 0 or 1, 2 pi clear of the
  // threshold: the torus absorbed even a bound 10^6 too small.)
  const test::Mesh sheet = test::WavySheet();
  const SdfGrid grid = GridAround(sheet.vertices, 24);
  const Comparison diff =
      Compare(SampleBruteForce(sheet.vertices, sheet.triangles, grid),
              SampleWithHierarchy(sheet.vertices, sheet.triangles, grid, {1.0, 1e-4}));
  EXPECT_GT(diff.differ, 0);
  EXPECT_EQ(diff.sign_only, diff.differ);
}

}  // namespace
}  // namespace viscera::collision
