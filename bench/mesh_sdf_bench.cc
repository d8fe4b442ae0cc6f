// Cost of building a mesh obstacle's distance field: scenes/cavity.toml's liver (scenes/liver.obj,
// 320 triangles, as the scene scales and places it) sampled at `resolution` cells along its
// longest side, by the brute force (every grid point against every triangle, kept as the
// reference) and by the hierarchy MeshSdf uses (collision/sdf_sampling.h). Both give
// the same samples bit for bit (tests/collision/sdf_sampling_test.cc).
//
//   BM_LiverField/hierarchy:H/resolution:R   one iteration = the whole field; H = 0 brute
//                                            force, 1 hierarchy. Counters: samples, and
//                                            exact_signs (grid points whose sign needed the
//                                            brute-force winding number).
//
// Alternate the two (a shared machine drifts): --benchmark_enable_random_interleaving=true
// --benchmark_repetitions=N. Figures: docs/benchmarks.md ("Mesh obstacles").
#include <benchmark/benchmark.h>

#include "collision/mesh_sdf.h"
#include "collision/sdf_sampling.h"
#include "common/types.h"

namespace viscera::collision {
namespace {

void BM_LiverField(benchmark::State& state) {
  const bool hierarchy = state.range(0) != 0;
  const int resolution = static_cast<int>(state.range(1));
  // the scene's placement; the field built here is thrown away, only its mesh is kept
  const MeshSdf liver =
      MeshSdf::FromObj(VISCERA_SOURCE_DIR "/scenes/liver.obj", 0.06, Vec3(0.07, 0.0, 0.245), 8);
  const SdfGrid grid = GridAround(liver.vertices(), resolution);
  SamplingStats stats;
  for (auto _ : state) {
    std::vector<double> samples =
        hierarchy ? SampleWithHierarchy(liver.vertices(), liver.faces(), grid, {}, &stats)
                  : SampleBruteForce(liver.vertices(), liver.faces(), grid);
    benchmark::DoNotOptimize(samples.data());
  }
  state.counters["samples"] = static_cast<double>(grid.size());
  state.counters["exact_signs"] = static_cast<double>(stats.exact_signs);
}
BENCHMARK(BM_LiverField)
    ->ArgNames({"hierarchy", "resolution"})
    ->Args({0, 40})
    ->Args({1, 40})
    ->Args({1, 100})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime();

}  // namespace
}  // namespace viscera::collision

BENCHMARK_MAIN();
