// What a scene from the network may cost, bounded from its keys before anything is allocated
// (SceneLimits), and the ranges every scene's tool parameters must lie in.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "common/check.h"
#include "scene/scene.h"

namespace viscera::scene {
namespace {

const std::string kTube =
    "[intestine]\nlength = 0.4\nradius = 0.0125\nmass = 0.1\ncontrol_points = 21\n"
    "[intestine.shape]\nkind = \"straight\"\n";

std::string Tools(int n, const std::string& extra = "") {
  std::string out;
  for (int i = 0; i < n; ++i)
    out += "[[tool]]\nname = \"t" + std::to_string(i) + "\"\nport = [0, 0, 0.3]\n" + extra;
  return out;
}

// The error ParseScene(text, limits) gives, "" when it accepts the scene.
std::string ErrorOf(const std::string& text, const SceneLimits& limits = {}) {
  try {
    ParseScene(text, "limits.toml", limits);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

SceneLimits Network() {
  SceneLimits limits;
  limits.max_spheres = 2000;
  limits.max_margin_radii = 4.0;
  limits.max_tools = 8;
  limits.max_mesh_triangles = 1000;
  return limits;
}

// A tiny radius asked for a sphere per 1e-9 m of tube (6.2 GB before the kill): refused from
// the two keys, before the chain exists.
TEST(SceneLimits, TheSphereCountIsBoundedFromLengthAndRadius) {
  EXPECT_EQ(ErrorOf(kTube, Network()), "");
  const std::string tiny =
      "[intestine]\nlength = 0.4\nradius = 1e-9\nmass = 0.1\ncontrol_points = 21\n"
      "[intestine.shape]\nkind = \"straight\"\n";
  EXPECT_NE(ErrorOf(tiny, Network())
                .find("intestine.length / intestine.radius = 4e+08 collision spheres: above "
                      "this server's limit of 2000"),
            std::string::npos)
      << ErrorOf(tiny, Network());
}

TEST(SceneLimits, TheContactMarginIsBoundedInRadii) {
  EXPECT_EQ(ErrorOf(kTube + "[contacts]\nmargin = 0.05\n", Network()), "");  // 4 radii
  EXPECT_NE(ErrorOf(kTube + "[contacts]\nmargin = 1.0\n", Network())
                .find("contacts.margin = 1 m: above this server's limit of 4 tube radii (0.05 m)"),
            std::string::npos);
}

TEST(SceneLimits, ToolsAreCounted) {
  EXPECT_EQ(ErrorOf(kTube + Tools(8), Network()), "");
  EXPECT_NE(ErrorOf(kTube + Tools(9), Network())
                .find("[[tool]] count = 9: above this server's limit of 8"),
            std::string::npos);
  EXPECT_EQ(ErrorOf(kTube + Tools(9)), "");  // local scenes: no limit
}

// Triangles are counted while the OBJ is read: a 2M-triangle mesh under the byte limit took
// 150 s to build.
TEST(SceneLimits, MeshTrianglesAreCountedWhileReading) {
  const std::string obj = ::testing::TempDir() + "/many.obj";
  {
    std::ofstream out(obj);
    out << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    for (int i = 0; i < 1001; ++i) out << "f 1 2 3\n";
  }
  const std::string mesh =
      kTube + "[[obstacle]]\nkind = \"mesh\"\nfile = \"" + obj + "\"\nresolution = 8\n";
  EXPECT_NE(ErrorOf(mesh, Network())
                .find("obstacle[0].file triangles = 1001: above this server's limit of 1000"),
            std::string::npos)
      << ErrorOf(mesh, Network());
}

// A stiffness or force limit of 1e308 and a mass of 1e-300 made 500 of 501 forces on the
// wire NaN or infinite: refused at load, with the key and the range.
TEST(SceneLimits, ToolParametersAreRangeChecked) {
  EXPECT_EQ(ErrorOf(kTube + Tools(1, "coupling_stiffness = 1e5\nmax_force = 100\nmass = 1e-3\n")),
            "");
  EXPECT_NE(ErrorOf(kTube + Tools(1, "coupling_stiffness = 1e308\n"))
                .find("tool[0].coupling_stiffness = 1e+308: outside +-1e+09"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kTube + Tools(1, "coupling_stiffness = 2e5\n"))
                .find("tool[0].coupling_stiffness = 200000: expected 0.001..100000 N/m"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kTube + Tools(1, "max_force = 1e6\n"))
                .find("tool[0].max_force = 1e+06: expected 0.001..100 N"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kTube + Tools(1, "mass = 1e-300\n"))
                .find("tool[0].mass = 1e-300: expected 0.001..10 kg"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kTube + "[contacts]\nstiffness = 1e300\n")
                .find("contacts.stiffness = 1e+300: outside +-1e+09"),
            std::string::npos);
}

TEST(SceneLimits, ContactParametersAreRangeChecked) {
  // At 1e6 N/m every closing pair of a falling tube was an impact: their impulses' dense system
  // took 7 GB, and a step minutes.
  EXPECT_EQ(
      ErrorOf(kTube + "[contacts]\nstiffness = 1e5\ndamping = 1000\ntangential_stiffness = 1e5\n"),
      "");
  EXPECT_NE(ErrorOf(kTube + "[contacts]\nstiffness = 1e6\n")
                .find("contacts.stiffness = 1e+06: expected 1..100000 N/m"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kTube + "[contacts]\ndamping = 1e4\n")
                .find("contacts.damping = 10000: expected 0..1000 N s/m"),
            std::string::npos);
  EXPECT_NE(ErrorOf(kTube + "[contacts]\ntangential_stiffness = 1e6\n")
                .find("contacts.tangential_stiffness = 1e+06"),
            std::string::npos);
}

}  // namespace
}  // namespace viscera::scene
