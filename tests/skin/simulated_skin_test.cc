// Skins of a simulated state, not a synthetic skeleton: the settled pile of scenes/fall.toml,
// where loops lie on each other. Every skin must be a closed surface with the tube's volume
// that does not pass through itself.
#include <gtest/gtest.h>

#include <fstream>
#include <numbers>
#include <sstream>

#include "mechanics/step.h"
#include "mesh_geometry.h"
#include "scene/scene.h"
#include "skin/skin.h"
#include "spline/catmull_rom.h"

namespace viscera::skin {
namespace {

Points SettledFall() {
  std::ifstream in(std::string(VISCERA_SOURCE_DIR) + "/scenes/fall.toml");
  std::stringstream text;
  text << in.rdbuf();
  const mechanics::Model model(
      scene::ParseScene(text.str(), std::string(VISCERA_SOURCE_DIR) + "/scenes/fall.toml").model);
  mechanics::State state = mechanics::InitialState(model);
  mechanics::Workspace workspace(model);
  const int steps = static_cast<int>(std::lround(4.0 * model.params().rate_hz));
  for (int k = 0; k < steps; ++k) mechanics::Step(model, {}, &state, &workspace);
  return state.q;
}

struct PileSkins {
  Points q = SettledFall();
  SkinOptions options;
  PileSkins() {
    options.radius = 0.0125;  // fall.toml's
    options.hybrid.focus = q.row(q.rows() / 2).transpose();
  }
  Mesh Build(const char* name) const {
    auto skin = MakeSkin(name, options);
    skin->Bind(static_cast<int>(q.rows()));
    Mesh mesh;
    skin->Build(q, &mesh);
    return mesh;
  }
};

TEST(SimulatedSkins, TheSettledPileGivesClosedSkinsWithTheTubesVolume) {
  const PileSkins pile;
  const double length = spline::CatmullRom(static_cast<int>(pile.q.rows())).Length(pile.q);
  const double volume = std::numbers::pi * pile.options.radius * pile.options.radius * length;
  for (const char* name : kSkinNames) {
    const Mesh mesh = pile.Build(name);
    EXPECT_TRUE(CheckTopology(mesh).closed_oriented_manifold()) << name;
    EXPECT_EQ(testing::BadVertexFans(mesh), 0) << name;
    EXPECT_NEAR(SignedVolume(mesh), volume, 0.05 * volume) << name;
  }
}

// KNOWN FAILURE (ctest WILL_FAIL, tests/CMakeLists.txt). Missing capabilities, both needed:
// a settled pile whose loops do not overlap (they sink into each other by ~17 % of R today,
// and ring skins of overlapping loops must cross; docs/contacts.md), and skins
// that do not cross themselves in bends tighter than R (ParametricSkinKnownFailure and
// ConvolutionSkinKnownFailure). The implicit skin (one field, marching cubes) passes already.
// When this starts passing, ctest reports a failure: drop the KnownFailure name then.
TEST(SimulatedSkinsKnownFailure, TheSettledPilesSkinsDoNotCrossThemselves) {
  const PileSkins pile;
  for (const char* name : kSkinNames)
    EXPECT_EQ(testing::SelfIntersections(pile.Build(name)), 0) << name;
}

}  // namespace
}  // namespace viscera::skin
