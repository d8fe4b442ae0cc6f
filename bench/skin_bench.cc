// Skin benchmark: meshes per second for each skin, single thread, and the growth with length.
//
//   BM_Fall*    the REAL settled pile: scenes/fall.toml (4 m, 250 control points) is simulated
//               for 3 s once at start-up (mechanics with contacts, ~0.2 s of CPU), and the last
//               kFallFrames steps (2.91-3.00 s) are kept; the benchmarks cycle through them, so
//               the convolution skin's warm start follows the pile's residual motion.
//   BM_* others a synthetic packed skeleton (a flat spiral of a 1.25 cm tube whose turns are
//               2.4 R apart, 250 control points on 4 m), the stand-in used before contacts
//               landed; it moves between frames (a travelling wave of 0.5 R amplitude across a
//               cycle of 8 poses). Kept for comparison and for the growth with length.
//
//   taskset -c 1 ./build/bench/bench_skin --benchmark_counters_tabular=true --benchmark_min_time=1
//   (--benchmark_filter=Fall for the settled pile only)
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "common/check.h"
#include "mechanics/step.h"
#include "scene/scene.h"

#include "skin/convolution_skin.h"
#include "skin/hybrid_skin.h"
#include "skin/skeletons.h"  // tests/skin/skeletons.h
#include "skin/skin.h"

namespace viscera::skin {
namespace {

constexpr double kR = 0.0125;
constexpr int kPoses = 8;

// 250 control points per 4 m, turns 2.4 R apart, innermost turn radius 4 R.
std::vector<Points> MovingSpiral(double length) {
  const int n = static_cast<int>(std::lround(250.0 * length / 4.0));
  const Points base = testing::FlatSpiral(n, length, 4 * kR, 2.4 * kR);
  std::vector<Points> poses;
  for (int f = 0; f < kPoses; ++f) {
    Points q = base;
    for (int i = 0; i < n; ++i)
      q(i, 2) += 0.5 * kR * std::sin(0.2 * i + 2.0 * std::numbers::pi * f / kPoses);
    poses.push_back(q);
  }
  return poses;
}

// The settled fall: the last kFallFrames control-point snapshots of 3 simulated seconds of
// scenes/fall.toml, and the scene's tube radius. Simulated once, on first use.
constexpr const char* kFallScene = VISCERA_SOURCE_DIR "/scenes/fall.toml";
constexpr double kFallSeconds = 3.0;
constexpr int kFallFrames = 10;

struct FallPile {
  std::vector<Points> frames;
  double radius = 0.0;
};

const FallPile& Fall() {
  static const FallPile pile = [] {
    const scene::Scene scene = scene::LoadSceneFile(kFallScene);
    const mechanics::Model model(scene.model);
    mechanics::Workspace workspace(model);
    mechanics::State state = mechanics::InitialState(model);
    const int steps = static_cast<int>(std::lround(kFallSeconds * model.params().rate_hz));
    FallPile p;
    p.radius = model.params().radius;
    for (int i = 0; i < steps; ++i) {
      mechanics::Step(model, {}, &state, &workspace);
      if (i >= steps - kFallFrames) p.frames.push_back(state.q);
    }
    ThrowUnless(state.nonfinite_resets == 0, kFallScene, ": the fall diverged");
    // What the skins see: the pile's extent and how much it still moves over the kept frames.
    const Points& q = p.frames.back();
    double motion = 0.0;
    for (size_t f = 1; f < p.frames.size(); ++f)
      motion = std::max(motion, (p.frames[f] - p.frames[f - 1]).rowwise().norm().maxCoeff());
    std::fprintf(
        stderr,
        "fall.toml settled at t = %.2f s: %d control points, radius %.4f m, x [%.3f, %.3f], "
        "y [%.3f, %.3f], z [%.3f, %.3f] m; largest control-point move per step over the last "
        "%d steps %.3g mm\n",
        state.t, static_cast<int>(q.rows()), p.radius, q.col(0).minCoeff(), q.col(0).maxCoeff(),
        q.col(1).minCoeff(), q.col(1).maxCoeff(), q.col(2).minCoeff(), q.col(2).maxCoeff(),
        kFallFrames, motion * 1e3);
    return p;
  }();
  return pile;
}

void Run(benchmark::State& state, Skin* skin, const std::vector<Points>& poses) {
  skin->Bind(static_cast<int>(poses[0].rows()));
  Mesh mesh;
  size_t frame = 0;
  skin->Build(poses[frame++ % poses.size()], &mesh);  // first frame: cold start, buffers sized
  long long evaluations = 0;
  for (auto _ : state) {
    skin->Build(poses[frame++ % poses.size()], &mesh);
    evaluations += skin->stats().field_evaluations;
    benchmark::DoNotOptimize(mesh.positions.data());
  }
  state.counters["meshes/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["triangles"] = mesh.num_triangles();
  state.counters["vertices"] = mesh.num_vertices();
  state.counters["evals/vertex"] = static_cast<double>(evaluations) /
                                   std::max<double>(1.0, state.iterations() * mesh.num_vertices());
}

void BM_Parametric(benchmark::State& state) {
  SkinOptions o;
  o.radius = kR;
  o.parametric.rings_per_segment = static_cast<int>(state.range(0));
  o.parametric.sides = static_cast<int>(state.range(1));
  auto skin = MakeSkin("parametric", o);
  Run(state, skin.get(), MovingSpiral(4.0));
}
BENCHMARK(BM_Parametric)
    ->Args({8, 16})
    ->Args({12, 16})
    ->Args({12, 32})
    ->Unit(benchmark::kMillisecond);

void BM_Convolution(benchmark::State& state) {
  SkinOptions o;
  o.radius = kR;
  o.convolution.sides = static_cast<int>(state.range(0));
  auto skin = MakeSkin("convolution", o);
  Run(state, skin.get(), MovingSpiral(4.0));
}
BENCHMARK(BM_Convolution)->Arg(16)->Arg(24)->Arg(32)->Unit(benchmark::kMillisecond);

void BM_ConvolutionStatic(benchmark::State& state) {
  SkinOptions o;
  o.radius = kR;
  o.convolution.sides = static_cast<int>(state.range(0));
  auto skin = MakeSkin("convolution", o);
  const std::vector<Points> moving = MovingSpiral(4.0);
  Run(state, skin.get(), std::vector<Points>(kPoses, moving[0]));
}
BENCHMARK(BM_ConvolutionStatic)->Arg(32)->Unit(benchmark::kMillisecond);

void BM_Implicit(benchmark::State& state) {
  SkinOptions o;
  o.radius = kR;
  o.implicit.cell_factor = state.range(0) / 100.0;
  o.implicit.blending_graph = state.range(1) != 0;
  auto skin = MakeSkin("implicit", o);
  Run(state, skin.get(), MovingSpiral(4.0));
}
BENCHMARK(BM_Implicit)
    ->Args({50, 1})
    ->Args({50, 0})
    ->Args({25, 1})
    ->Args({25, 0})
    ->Unit(benchmark::kMillisecond);

void BM_Hybrid(benchmark::State& state) {
  SkinOptions o;
  o.radius = kR;
  o.hybrid.focus = Vec3(0.0, 0.0, 0.0);  // the spiral's centre
  o.hybrid.focus_radius = state.range(0) / 100.0;
  o.hybrid.transition = 0.05;
  auto skin = MakeSkin("hybrid", o);
  Run(state, skin.get(), MovingSpiral(4.0));
}
BENCHMARK(BM_Hybrid)->Arg(10)->Arg(20)->Unit(benchmark::kMillisecond);

// The same configurations on the settled scenes/fall.toml pile (kFallFrames frames cycled).
void BM_FallParametric(benchmark::State& state) {
  SkinOptions o;
  o.radius = Fall().radius;
  o.parametric.rings_per_segment = static_cast<int>(state.range(0));
  o.parametric.sides = static_cast<int>(state.range(1));
  auto skin = MakeSkin("parametric", o);
  Run(state, skin.get(), Fall().frames);
}
BENCHMARK(BM_FallParametric)
    ->Args({8, 16})
    ->Args({12, 16})
    ->Args({12, 32})
    ->Unit(benchmark::kMillisecond);

void BM_FallConvolution(benchmark::State& state) {
  SkinOptions o;
  o.radius = Fall().radius;
  o.convolution.sides = static_cast<int>(state.range(0));
  auto skin = MakeSkin("convolution", o);
  Run(state, skin.get(), Fall().frames);
}
BENCHMARK(BM_FallConvolution)->Arg(16)->Arg(24)->Arg(32)->Unit(benchmark::kMillisecond);

// The last settled frame only: a still pile (warm start from the same skeleton).
void BM_FallConvolutionStatic(benchmark::State& state) {
  SkinOptions o;
  o.radius = Fall().radius;
  o.convolution.sides = static_cast<int>(state.range(0));
  auto skin = MakeSkin("convolution", o);
  Run(state, skin.get(), std::vector<Points>{Fall().frames.back()});
}
BENCHMARK(BM_FallConvolutionStatic)->Arg(32)->Unit(benchmark::kMillisecond);

void BM_FallImplicit(benchmark::State& state) {
  SkinOptions o;
  o.radius = Fall().radius;
  o.implicit.cell_factor = state.range(0) / 100.0;
  o.implicit.blending_graph = state.range(1) != 0;
  auto skin = MakeSkin("implicit", o);
  Run(state, skin.get(), Fall().frames);
}
BENCHMARK(BM_FallImplicit)
    ->Args({50, 1})
    ->Args({50, 0})
    ->Args({25, 1})
    ->Args({25, 0})
    ->Unit(benchmark::kMillisecond);

// Focus at the pile's centroid (viscera-sim's default for --skin hybrid), radius in cm. The
// pile is about 20 cm across, so a focus of 10 cm plus the 5 cm band already covers all of it.
void BM_FallHybrid(benchmark::State& state) {
  SkinOptions o;
  o.radius = Fall().radius;
  o.hybrid.focus = Fall().frames.back().colwise().mean().transpose();
  o.hybrid.focus_radius = state.range(0) / 100.0;
  o.hybrid.transition = 0.05;
  auto skin = MakeSkin("hybrid", o);
  Run(state, skin.get(), Fall().frames);
}
BENCHMARK(BM_FallHybrid)->Arg(5)->Arg(10)->Unit(benchmark::kMillisecond);

// Growth with length (control points proportional to length, 62.5 per metre).
void BM_LengthParametric(benchmark::State& state) {
  SkinOptions o;
  o.radius = kR;
  auto skin = MakeSkin("parametric", o);
  Run(state, skin.get(), MovingSpiral(static_cast<double>(state.range(0))));
}
BENCHMARK(BM_LengthParametric)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Unit(benchmark::kMillisecond);

void BM_LengthConvolution(benchmark::State& state) {
  SkinOptions o;
  o.radius = kR;
  auto skin = MakeSkin("convolution", o);
  Run(state, skin.get(), MovingSpiral(static_cast<double>(state.range(0))));
}
BENCHMARK(BM_LengthConvolution)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Unit(benchmark::kMillisecond);

void BM_LengthImplicit(benchmark::State& state) {
  SkinOptions o;
  o.radius = kR;
  o.implicit.cell_factor = 0.5;
  auto skin = MakeSkin("implicit", o);
  Run(state, skin.get(), MovingSpiral(static_cast<double>(state.range(0))));
}
BENCHMARK(BM_LengthImplicit)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace viscera::skin

BENCHMARK_MAIN();
