// Rendering benchmark: wall milliseconds per frame of the cavity scene for each skin and frame
// size, split into skin build, render (upload, draw, glFinish) and JPEG encode (quality 85).
//
//   scenes/cavity.toml (3 m, 190 control points, cavity wall, spine, liver, bladder) settles
//   for 3 s at load; the benchmark then steps it 10 more steps and cycles through those
//   poses, so the convolution skin's warm start follows real residual motion. The camera is
//   viscera-sim's default (the scene's [camera] laparoscope, else the framing of the pile).
//   LP_NUM_THREADS=0 unless set: llvmpipe rasterizes in the benchmark's thread, so the figures
//   are one core's. cpu_ms is the process's CPU time per frame (skin, draw, JPEG, and llvmpipe's
//   own threads when LP_NUM_THREADS >= 1): on a loaded machine the wall times include waiting,
//   the CPU time does not.
//
//   draw_ms (culling, uploads, draw calls: llvmpipe's vertex work and binning) and finish_ms
//   (glFinish: rasterization and fragment shading still under way) split render_ms.
//
//   taskset -c 1 ./build/bench/bench_render --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "common/check.h"
#include "mechanics/step.h"
#include "render/frame_renderer.h"
#include "render/port_scope.h"
#include "scene/scene.h"

namespace viscera::render {
namespace {

// CPU time of every thread of the process (ns).
int64_t ProcessCpuNanos() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

constexpr const char* kScene = VISCERA_SOURCE_DIR "/scenes/cavity.toml";
constexpr int kPoses = 10;
constexpr const char* kSkins[] = {"parametric", "convolution", "implicit", "hybrid"};

struct Cavity {
  mechanics::ModelParams params;
  std::vector<Points> poses;
};

const Cavity& Scene() {
  static const Cavity cavity = [] {
    Cavity c;
    c.params = scene::LoadSceneFile(kScene).model;  // settles for 3 s
    const mechanics::Model model(c.params);
    mechanics::Workspace workspace(model);
    mechanics::State state = mechanics::InitialState(model);
    for (int i = 0; i < kPoses; ++i) {
      mechanics::Step(model, {}, &state, &workspace);
      c.poses.push_back(state.q);
    }
    ThrowUnless(state.nonfinite_resets == 0, kScene, ": diverged");
    return c;
  }();
  return cavity;
}

// Args: skin index, width, height, sides (vertices per ring of the ring-based skins; 0: the
// skin's default, 16 parametric, 32 convolution and hybrid), textures (0 plain, 1 procedural),
// camera (1 the scene's default, 0 the framing camera from outside: the view before [camera]).
void BM_Frame(benchmark::State& state) {
  const Cavity& cavity = Scene();
  FrameOptions options;
  options.skin = kSkins[state.range(0)];
  options.width = static_cast<int>(state.range(1));
  options.height = static_cast<int>(state.range(2));
  if (state.range(3) > 0) {
    options.skin_options.parametric.sides = static_cast<int>(state.range(3));
    options.skin_options.convolution.sides = static_cast<int>(state.range(3));
  }
  options.scene.textures = state.range(4) != 0;
  FrameRenderer renderer(cavity.params, options);
  const Points& q0 = cavity.poses.front();
  const bool framing = state.range(5) == 0;
  const Laparoscope scope =
      framing
          ? FramingLaparoscope(q0.colwise().minCoeff().transpose(),
                               q0.colwise().maxCoeff().transpose(), options.width, options.height)
          : SceneLaparoscope(cavity.params, q0, options.width, options.height);
  double skin_ms = 0.0, render_ms = 0.0, draw_ms = 0.0, finish_ms = 0.0, encode_ms = 0.0,
         bytes = 0.0, kept = 0.0;
  size_t k = 0;
  const int64_t cpu0 = ProcessCpuNanos();
  for (auto _ : state) {
    renderer.Render(cavity.poses[k++ % cavity.poses.size()], {}, scope);
    bytes += static_cast<double>(renderer.Encode().size());
    skin_ms += renderer.timings().skin_ms;
    render_ms += renderer.timings().render_ms;
    draw_ms += renderer.timings().draw_ms;
    finish_ms += renderer.timings().finish_ms;
    encode_ms += renderer.timings().encode_ms;
    kept += renderer.scene().intestine_kept() ? 1.0 : 0.0;
  }
  const double cpu_ms = static_cast<double>(ProcessCpuNanos() - cpu0) * 1e-6;
  const double n = static_cast<double>(state.iterations());
  state.SetLabel(
      options.skin + (state.range(3) > 0 ? ", " + std::to_string(state.range(3)) + " sides" : "") +
      (options.scene.textures ? ", textured" : ", plain") + (framing ? ", framing camera" : ""));
  state.counters["cpu_ms"] = cpu_ms / n;
  state.counters["skin_ms"] = skin_ms / n;
  state.counters["render_ms"] = render_ms / n;
  state.counters["draw_ms"] = draw_ms / n;
  state.counters["finish_ms"] = finish_ms / n;
  state.counters["encode_ms"] = encode_ms / n;
  state.counters["render+encode fps"] = 1e3 / ((render_ms + encode_ms) / n);
  state.counters["frame fps"] = 1e3 / ((skin_ms + render_ms + encode_ms) / n);
  state.counters["triangles"] = static_cast<double>(renderer.scene().triangles());
  state.counters["skin_drawn"] =
      static_cast<double>(renderer.scene().intestine_counts().triangles_drawn);
  state.counters["jpeg_kB"] = bytes / n / 1024.0;
  state.counters["kept"] = kept / n;  // frames drawn over the kept picture of a resting bowel
}

// The load tester's session (tools/loadtest.py): the bowel at rest (the first pose, every frame),
// the tools' tips on a 1 cm circle above the pile, half a turn a second at 25 Hz frames, through
// the scene's laparoscope, parametric skin, 640x480. Arg: keep the intestine's picture (1) or
// draw it every frame (0).
void BM_FrameRestingBowel(benchmark::State& state) {
  const Cavity& cavity = Scene();
  FrameOptions options;
  options.scene.keep_intestine = state.range(0) != 0;
  FrameRenderer renderer(cavity.params, options);
  const Points& q0 = cavity.poses.front();
  const Laparoscope scope = SceneLaparoscope(cavity.params, q0, options.width, options.height);
  std::vector<mechanics::ToolState> tools(cavity.params.tools.size());
  double skin_ms = 0.0, render_ms = 0.0, encode_ms = 0.0, kept = 0.0;
  int k = 0;
  const int64_t cpu0 = ProcessCpuNanos();
  for (auto _ : state) {
    const double a = 2.0 * 3.141592653589793 * 0.5 * (k++) / 25.0;
    for (size_t i = 0; i < tools.size(); ++i) {
      tools[i].initialized = true;
      tools[i].tip =
          Vec3(0.01 * std::cos(a) + 0.03 * static_cast<double>(i), 0.01 * std::sin(a), 0.15);
    }
    renderer.Render(q0, tools, scope);
    renderer.Encode();
    skin_ms += renderer.timings().skin_ms;
    render_ms += renderer.timings().render_ms;
    encode_ms += renderer.timings().encode_ms;
    kept += renderer.scene().intestine_kept() ? 1.0 : 0.0;
  }
  const double n = static_cast<double>(state.iterations());
  state.SetLabel(options.scene.keep_intestine ? "kept intestine" : "intestine drawn");
  state.counters["cpu_ms"] = static_cast<double>(ProcessCpuNanos() - cpu0) * 1e-6 / n;
  state.counters["skin_ms"] = skin_ms / n;
  state.counters["render_ms"] = render_ms / n;
  state.counters["encode_ms"] = encode_ms / n;
  state.counters["kept"] = kept / n;
}
BENCHMARK(BM_FrameRestingBowel)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void Sizes(benchmark::internal::Benchmark* b) {
  for (int skin = 0; skin < 4; ++skin) {
    b->Args({skin, 640, 480, 0, 1, 1});
    b->Args({skin, 1280, 720, 0, 1, 1});
  }
  // the convolution surface at the parametric skin's ring density
  for (int skin : {1, 3}) {
    b->Args({skin, 640, 480, 16, 1, 1});
    b->Args({skin, 1280, 720, 16, 1, 1});
  }
  // what the laparoscope's look costs at 640x480: the same frames plain, and plain through the
  // framing camera (the view before [camera] and the textures); the server's skins (16 sides)
  for (int sides : {0, 16}) {
    b->Args({1, 640, 480, sides, 0, 1});
    b->Args({1, 640, 480, sides, 0, 0});
  }
  b->Args({0, 640, 480, 0, 0, 1});
  b->Args({0, 640, 480, 0, 0, 0});
}
BENCHMARK(BM_Frame)->Apply(Sizes)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace viscera::render

BENCHMARK_MAIN();
