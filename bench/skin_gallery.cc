// Writes the example meshes behind the pictures in docs/ (docs/skins.md): every skin on a
// packed 1.5 m flat spiral (turns 2.4 R apart) and, for the blending comparison, on a
// hairpin whose arms are 1.6 R apart. Render them with tools/plot_mesh.py.
//
//   ./build/bench/skin_gallery OUT_DIR
#include <cstdio>
#include <string>

#include "common/check.h"
#include "skin/skeletons.h"  // tests/skin/skeletons.h
#include "skin/skin.h"

namespace {

int Run(const std::string& dir) {
  using namespace viscera;
  using namespace viscera::skin;
  constexpr double kR = 0.0125;
  const Points spiral = testing::FlatSpiral(94, 1.5, 4 * kR, 2.4 * kR);
  const Points hairpin = testing::Hairpin(60, 12 * kR, 1.6 * kR);
  auto write = [&](const std::string& name, SkinOptions options, const Points& q,
                   const std::string& file) {
    options.radius = kR;
    auto skin = MakeSkin(name, options);
    skin->Bind(static_cast<int>(q.rows()));
    Mesh mesh;
    skin->Build(q, &mesh);
    WriteMesh(dir + "/" + file, mesh);
    std::printf("%-28s %-12s %7d triangles\n", file.c_str(), name.c_str(), mesh.num_triangles());
  };
  SkinOptions base;
  for (const char* name : {"parametric", "implicit", "convolution"}) {
    write(name, base, spiral, std::string("spiral_") + name + ".obj");
  }
  // hybrid: focus on the outer turns (x = 0.1 m), so both parts and the band show
  SkinOptions hybrid = base;
  hybrid.hybrid.focus = Vec3(0.12, 0.0, 0.0);
  hybrid.hybrid.focus_radius = 0.06;
  hybrid.hybrid.transition = 0.04;
  write("hybrid", hybrid, spiral, "spiral_hybrid.obj");
  // blending control on / off
  write("implicit", base, hairpin, "hairpin_implicit_graph.obj");
  SkinOptions no_graph = base;
  no_graph.implicit.blending_graph = false;
  write("implicit", no_graph, hairpin, "hairpin_implicit_nograph.obj");
  write("convolution", base, hairpin, "hairpin_convolution_local.obj");
  SkinOptions global = base;
  global.convolution.local = false;
  write("convolution", global, hairpin, "hairpin_convolution_global.obj");
  // parametric in a bend tighter than Rmax: folded rings
  write("parametric", base, testing::UBend(60, 8 * kR, 0.6 * kR), "ubend_parametric_fold.obj");
  write("parametric", base, testing::UBend(60, 8 * kR, 2.0 * kR), "ubend_parametric_ok.obj");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
    return 2;
  }
  try {
    return Run(argv[1]);
  } catch (const viscera::InputError& e) {
    std::fprintf(stderr, "skin_gallery: %s\n", e.what());
    return 1;
  }
}
