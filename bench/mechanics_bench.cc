// Cost of the mechanical layer on the paper's benchmark scene (scenes/fall.toml: a 4 m coil
// falling under gravity, contacts not simulated), for 50 to 1000 control points.
// Figures and the command that produced them: docs/benchmarks.md ("Mechanics").
//
// Every size is the same physical scene: the TOML text is re-parsed with another
// intestine.control_points, so the shape loader lays the same helix out at equal arc length
// and the springs' stiffness and masses follow from the same EA, EI and mass.
#include <benchmark/benchmark.h>

#include <string>

#include "common/check.h"
#include "fall_scene.h"
#include "mechanics/forces.h"
#include "mechanics/mass_solver.h"
#include "mechanics/stability.h"
#include "mechanics/step.h"
#include "scene/scene.h"

namespace viscera::mechanics {
namespace {

// A run of steps restarts from the coil after this much simulated time, so every size measures
// the first second of the fall, not a chain that has been in free fall for minutes.
constexpr double kRestartAfterSeconds = 1.0;

// The fall scene with `n` control points, without contacts: the mechanical layer alone.
ModelParams FallParams(int n) {
  ModelParams params = bench::FallParams(n);
  params.contacts.self = false;
  params.obstacles.clear();
  return params;
}

// RK4 sub-steps that keep the fall stable at this size (estimated at the starting coil).
int StableRk4Substeps(ModelParams params) {
  params.integrator = IntegratorKind::kRk4;
  params.substeps = 1;
  const Model model(std::move(params));
  return EstimateStability(model, InitialState(model)).stable_substeps;
}

// Times Step on `params` and reports, besides the time per step:
//   substeps       integrator sub-steps per step
//   h_rate         h * rate_max of the sub-step (RK4 is stable below 2.8)
//   cpu_per_sim_s  CPU seconds per simulated second
//   realtime_x     simulated seconds per CPU second (the real-time factor on one core)
//   resets         non-finite steps (must be 0, or the figures are meaningless)
void RunSteps(benchmark::State& bench, ModelParams params) {
  const Model model(std::move(params));
  Workspace workspace(model);
  const State start = InitialState(model);
  State state = start;
  const double h_rate = EstimateStability(model, start).h_times_rate;
  const int64_t restart_steps = static_cast<int64_t>(kRestartAfterSeconds * model.params().rate_hz);

  // One warm-up step: the solvers size their workspace on first use.
  Step(model, {}, &state, &workspace);
  state = start;

  int64_t resets = 0;
  for (auto _ : bench) {
    Step(model, {}, &state, &workspace);
    if (state.steps >= restart_steps) {
      bench.PauseTiming();
      resets += state.nonfinite_resets;
      state = start;  // same sizes: a copy, no allocation
      bench.ResumeTiming();
    }
  }
  resets += state.nonfinite_resets;

  const double simulated = static_cast<double>(bench.iterations()) * model.step_size();
  bench.counters["n"] = model.num_points();
  bench.counters["substeps"] = model.params().substeps;
  bench.counters["h_rate"] = h_rate;
  bench.counters["cpu_per_sim_s"] =
      benchmark::Counter(simulated, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  bench.counters["realtime_x"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
  bench.counters["resets"] = static_cast<double>(resets);
}

// The scene as shipped: linearly implicit Euler, one sub-step at 100 Hz, its system
// M + h D + h^2 K solved by the 3x3 block-band Cholesky (cholmod:0) or CHOLMOD (cholmod:1).
void BM_FallImplicit(benchmark::State& bench) {
  ModelParams params = FallParams(static_cast<int>(bench.range(0)));
  params.integrator = IntegratorKind::kImplicitEuler;
  params.linear_solver =
      bench.range(1) == 0 ? LinearSolverKind::kBlockBand : LinearSolverKind::kCholmod;
  RunSteps(bench, std::move(params));
}

// RK4 at 100 Hz with the smallest stable sub-step count for this size (it grows with n: the
// stiffest spring, EA / l0, stiffens as the segments shorten).
void BM_FallRk4Stable(benchmark::State& bench) {
  ModelParams params = FallParams(static_cast<int>(bench.range(0)));
  params.integrator = IntegratorKind::kRk4;
  params.substeps = StableRk4Substeps(params);
  RunSteps(bench, std::move(params));
}

// One RK4 step with a fixed sub-step count (1) at every size: 4 force evaluations and 4
// constrained mass solves, so the time per step shows how one evaluation grows with n. The step
// is 10 us so that it is stable at every size (h_rate < 2.8); cpu_per_sim_s means nothing here.
void BM_Rk4OneSubstep(benchmark::State& bench) {
  ModelParams params = FallParams(static_cast<int>(bench.range(0)));
  params.integrator = IntegratorKind::kRk4;
  params.rate_hz = 1.0e5;
  params.substeps = 1;
  RunSteps(bench, std::move(params));
}

// The force evaluation alone, with and without the Jacobians the implicit step needs.
void BM_Forces(benchmark::State& bench) {
  const Model model(FallParams(static_cast<int>(bench.range(0))));
  const bool with_jacobians = bench.range(1) != 0;
  const State state = InitialState(model);
  StretchScratch scratch;
  scratch.Resize(model.num_points());
  ForceJacobians jacobians;
  jacobians.Resize(model.num_points());
  Points force(model.num_points(), 3);
  for (auto _ : bench) {
    ComputeForces(model, state.q, state.qd, {}, &scratch, &force, nullptr,
                  with_jacobians ? &jacobians : nullptr);
    benchmark::DoNotOptimize(force.data());
    benchmark::ClobberMemory();
  }
  bench.counters["n"] = model.num_points();
}

// One mass solve M X = B, 3 right-hand sides (#n by 3), through MassSolver with the banded
// Cholesky (kind 0) or CHOLMOD (kind 1). Each iteration first restores B (an n x 3 copy, the
// same for both; BM_RhsCopy times it alone), since solving in place repeatedly would overflow.
void BM_MassSolve(benchmark::State& bench) {
  ModelParams params = FallParams(static_cast<int>(bench.range(0)));
  params.mass_solver = bench.range(1) == 0 ? MassSolverKind::kBanded : MassSolverKind::kCholmod;
  const Model model(std::move(params));
  MassSolver solver(model);
  const Points rhs = model.gravity_force();
  Points b = rhs;
  solver.SolveInPlace(&b);  // warm-up: CHOLMOD sizes its workspace
  for (auto _ : bench) {
    b = rhs;
    solver.SolveInPlace(&b);
    benchmark::DoNotOptimize(b.data());
    benchmark::ClobberMemory();
  }
  bench.counters["n"] = model.num_points();
}

void BM_RhsCopy(benchmark::State& bench) {
  const Points rhs = Points::Random(bench.range(0), 3);
  Points b = rhs;
  for (auto _ : bench) {
    b = rhs;
    benchmark::DoNotOptimize(b.data());
    benchmark::ClobberMemory();
  }
}

void Sizes(benchmark::internal::Benchmark* b) {
  for (int n : {50, 125, 250, 500, 1000}) b->Arg(n);
}

void SizesTimesTwo(benchmark::internal::Benchmark* b) {
  for (int flag : {0, 1}) {
    for (int n : {50, 125, 250, 500, 1000}) b->Args({n, flag});
  }
}

BENCHMARK(BM_FallImplicit)
    ->Apply(SizesTimesTwo)
    ->ArgNames({"n", "cholmod"})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FallRk4Stable)->Apply(Sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Rk4OneSubstep)->Apply(Sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Forces)
    ->Apply(SizesTimesTwo)
    ->ArgNames({"n", "jacobians"})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MassSolve)
    ->Apply(SizesTimesTwo)
    ->ArgNames({"n", "cholmod"})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RhsCopy)->Apply(Sizes)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace viscera::mechanics

BENCHMARK_MAIN();
