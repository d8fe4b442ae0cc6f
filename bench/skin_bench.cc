// Skin benchmark: meshes per second for each skin on a packed 4 m, 250-control-point
// skeleton (a flat spiral of a 1.25 cm tube whose turns are 2.4 R apart, standing in for the
// settled scenes/fall.toml until contacts land), single thread, and the growth with length.
//
// The skeleton moves between frames (a travelling wave of 0.5 R amplitude across a cycle of
// 8 poses), so temporally coherent skins do real work every frame.
//
//   ./build/bench/bench_skin --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "skin/convolution_skin.h"
#include "skin/hybrid_skin.h"
#include "skin/skin.h"
#include "skin/skeletons.h"  // tests/skin/skeletons.h

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
    for (int i = 0; i < n; ++i) q(i, 2) += 0.5 * kR * std::sin(0.2 * i + 2.0 * std::numbers::pi * f / kPoses);
    poses.push_back(q);
  }
  return poses;
}

void Run(benchmark::State& state, Skin* skin, const std::vector<Points>& poses) {
  skin->Bind(static_cast<int>(poses[0].rows()));
  Mesh mesh;
  int frame = 0;
  skin->Build(poses[frame++ % kPoses], &mesh);  // first frame: cold start, buffers sized
  long long evaluations = 0;
  for (auto _ : state) {
    skin->Build(poses[frame++ % kPoses], &mesh);
    evaluations += skin->stats().field_evaluations;
    benchmark::DoNotOptimize(mesh.positions.data());
  }
  state.counters["meshes/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["triangles"] = mesh.num_triangles();
  state.counters["vertices"] = mesh.num_vertices();
  state.counters["evals/vertex"] =
      static_cast<double>(evaluations) / std::max<double>(1.0, state.iterations() * mesh.num_vertices());
}

void BM_Parametric(benchmark::State& state) {
  SkinOptions o;
  o.radius = kR;
  o.parametric.rings_per_segment = static_cast<int>(state.range(0));
  o.parametric.sides = static_cast<int>(state.range(1));
  auto skin = MakeSkin("parametric", o);
  Run(state, skin.get(), MovingSpiral(4.0));
}
BENCHMARK(BM_Parametric)->Args({8, 16})->Args({12, 16})->Args({12, 32})->Unit(benchmark::kMillisecond);

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
BENCHMARK(BM_Implicit)->Args({50, 1})->Args({50, 0})->Args({25, 1})->Args({25, 0})->Unit(benchmark::kMillisecond);

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
