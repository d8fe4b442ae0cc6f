// Cost of the mechanics WITH contacts on the paper's benchmark scene (scenes/fall.toml: a 4 m
// coil falling onto a plane, self-contacts on), for 50 to 1000 control points.
// Figures and the commands: docs/benchmarks.md ("Cavity clearing", "Fall and coil", "Mesentery").
//
// Every size is the same physical scene: the TOML text is re-parsed with another
// intestine.control_points (bench/mechanics_bench.cc does the same without contacts). The sphere
// chain does not depend on the control points (spacing = radius: 4 m / 12.5 mm, 321 spheres),
// so the contact work is roughly the same at every size and only the curve's part grows with n.
//
//   BM_FallWhole/n:N/self:S    one iteration = the whole fall from the coil: 3 simulated
//                              seconds (300 steps: falling, impact at about 0.16 s, landing,
//                              the pile sliding and settling, which takes until about 2.8 s).
//                              The state is reset to the coil between iterations (not timed).
//   BM_FallWholeLimiterOnly/n:N  the same with the impact limiter and the stiffening law alone
//                              ([contacts] impact_constraints = false, spheres = "arc_length"),
//                              without the impacts held inside the implicit solve (the default).
//   BM_FallSettled/n:N/self:S  the settled pile: 3 simulated seconds of warm-up (not timed),
//                              then one iteration = one step.
// S = 1 is the scene as shipped; S = 0 turns self-contacts off (the plane stays) to show what
// self-contacts cost on top of the plane.
//
//   BM_CavityClearing/rate:R   the clinical scene: scenes/cavity.toml (settled at its 100 Hz, not
//                              timed) driven by scenes/clearing.csv at R Hz with the scene's
//                              sub-step length; one iteration = the whole 5.5 s gesture. Counters
//                              add p99_us (per step, thread CPU time), deepest_pct_r (deepest
//                              pair at any step, % of the radius) and peak_force (N, on the hand).
//   BM_PaperCoilFall/rate:R    the peers' benchmark: bench/scenes/paper_coil.toml, the
//                              paper's 4 m, 250-point coil (EI 1.9e-3 N m^2) falling 30 cm, at
//                              R Hz (the scene's sub-step length); one iteration = 2 simulated
//                              seconds from the release (reset between iterations, not timed).
//                              Counters add deepest_pct_r (deepest pair after any step, % of R),
//                              deepest_at_s (when), end_pct_r (after the last step, at 2 s) and
//                              x_pybullet: pybullet's CPU time per simulated second on this run
//                              (2.46 s, from the requirements' table of peers) over ours.
//   BM_CavityMesentery/term:T  scenes/cavity.toml settled, then one iteration = one
//                              step (T = 0) or only the mesentery's force term with its
//                              stiffness and damping blocks (T = 1, every tether taut: the
//                              term's worst case), 2 sub-steps each as the scene runs it:
//                              their ratio is the term's share of a step.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/check.h"
#include "common/clock.h"
#include "common/quantile.h"
#include "fall_scene.h"
#include "mechanics/implicit_euler.h"
#include "mechanics/mesentery_forces.h"
#include "mechanics/step.h"
#include "scene/scene.h"
#include "script/scripted_tools.h"

namespace viscera::mechanics {
namespace {

using bench::SceneAtRate;

// Simulated seconds of one whole-fall iteration, and of the warm-up before the settled runs.
constexpr double kFallSeconds = 3.0;
constexpr double kWarmupSeconds = 3.0;

// The fall scene with `n` control points, self-contacts on or off.
ModelParams FallParams(int n, bool self_contacts) {
  ModelParams params = bench::FallParams(n);
  VISCERA_DEMAND(params.contacts.self);  // the scene as shipped has them
  params.contacts.self = self_contacts;
  return params;
}

// What the steps did, summed over the timed steps.
struct Tally {
  int64_t steps = 0;
  int64_t substeps = 0;
  int max_substeps = 0;
  int64_t self_contacts = 0;
  int64_t environment_contacts = 0;
  double deepest = 0.0;     // m, the deepest pair after any step
  double deepest_at = 0.0;  // s, when

  void Add(const State& state) {
    ++steps;
    substeps += state.substeps;
    max_substeps = std::max(max_substeps, state.substeps);
    self_contacts += state.contacts.self;
    environment_contacts += state.contacts.environment;
    if (-state.contacts.min_clearance > deepest) {  // false for NaN (no pairs)
      deepest = -state.contacts.min_clearance;
      deepest_at = state.t;
    }
  }
};

// A scene file's model at `rate_hz`, with the scene's sub-step length.
// Counters (CPU time; "per step" means per 10 ms step of the scene's 100 Hz):
//   n, spheres       control points, spheres of the chain
//   us_per_step      CPU microseconds per step
//   ms_per_sim_s     CPU milliseconds per simulated second
//   realtime_x       simulated seconds per CPU second: the real-time factor on one core
//   ns_per_point     CPU nanoseconds per step and control point (flat = linear in n)
//   substeps         average integrator sub-steps per step (more at impacts); max_substeps
//   self, env        average self and environment contacts (pairs in contact) per step
//   resets           non-finite steps (must be 0, or the figures are meaningless)
//   searches_per_step  broad-phase searches (Verlet list rebuilds) per step
//   cg_per_substep   the exact coupling's CG iterations per integrator sub-step
void Report(benchmark::State& bench, const Model& model, int spheres, const Tally& tally,
            int64_t resets, Workspace& workspace) {
  const double steps = static_cast<double>(tally.steps);
  const double simulated = steps * model.step_size();
  const double n = model.num_points();
  using C = benchmark::Counter;
  bench.counters["n"] = n;
  bench.counters["spheres"] = spheres;
  bench.counters["us_per_step"] = C(steps * 1e-6, C::kIsRate | C::kInvert);
  bench.counters["ms_per_sim_s"] = C(simulated * 1e-3, C::kIsRate | C::kInvert);
  bench.counters["realtime_x"] = C(simulated, C::kIsRate);
  bench.counters["ns_per_point"] = C(steps * n * 1e-9, C::kIsRate | C::kInvert);
  bench.counters["substeps"] = static_cast<double>(tally.substeps) / steps;
  bench.counters["max_substeps"] = tally.max_substeps;
  bench.counters["self"] = static_cast<double>(tally.self_contacts) / steps;
  bench.counters["env"] = static_cast<double>(tally.environment_contacts) / steps;
  bench.counters["resets"] = static_cast<double>(resets);
  // Broad-phase searches per step (the Verlet list's rebuilds; since the workspace was made).
  if (workspace.interactions()) {
    bench.counters["searches_per_step"] =
        static_cast<double>(workspace.interactions()->searches()) / steps;
    bench.counters["partial_per_step"] =
        static_cast<double>(workspace.interactions()->partial_searches()) / steps;
  }
  if (const auto* implicit =
          dynamic_cast<const ImplicitEulerIntegrator*>(&workspace.integrator())) {
    // Since the workspace was made (warm-ups included): the exact coupling's work per sub-step.
    bench.counters["cg_per_substep"] =
        static_cast<double>(implicit->cg_iterations()) / std::max<int64_t>(1, implicit->substeps());
    // Solves done again per step: a contact's stick or slip revised (of which without evaluating
    // the sub-step again: friction_resolves), a tip contact revised, a
    // BDF2 sub-step taken again as backward Euler (impacts, stretch), a sub-step halved.
    bench.counters["friction_redos"] = static_cast<double>(implicit->friction_redos()) / steps;
    bench.counters["friction_resolves"] =
        static_cast<double>(implicit->friction_resolves()) / steps;
    bench.counters["tip_redos"] = static_cast<double>(implicit->tip_redos()) / steps;
    bench.counters["bdf2_redos"] =
        static_cast<double>(implicit->impact_redos() + implicit->stretch_redos()) / steps;
    bench.counters["halved"] = static_cast<double>(implicit->halved_substeps()) / steps;
    if (model.params().contacts.impact_constraints) {
      bench.counters["impact_substeps"] = static_cast<double>(implicit->impact_substeps()) / steps;
      bench.counters["impact_contacts"] = static_cast<double>(implicit->impact_contacts()) /
                                          std::max<int64_t>(1, implicit->impact_substeps());
    }
  }
}

void RunFallWhole(benchmark::State& bench, const ModelParams& params) {
  const Model model(params);
  Workspace workspace(model);
  const State start = InitialState(model);
  State state = start;
  const int64_t steps_per_fall = static_cast<int64_t>(kFallSeconds * model.params().rate_hz + 0.5);

  // One warm-up step: the solvers and the contact buffers size themselves on first use.
  Step(model, {}, &state, &workspace);

  Tally tally;
  int64_t resets = 0;
  for (auto _ : bench) {
    bench.PauseTiming();
    resets += state.nonfinite_resets;
    state = start;  // same sizes: a copy, no allocation
    bench.ResumeTiming();
    for (int64_t i = 0; i < steps_per_fall; ++i) {
      Step(model, {}, &state, &workspace);
      tally.Add(state);
    }
  }
  resets += state.nonfinite_resets;
  Report(bench, model, workspace.interactions()->chain().size(), tally, resets, workspace);
}

void BM_FallWhole(benchmark::State& bench) {
  RunFallWhole(bench, FallParams(static_cast<int>(bench.range(0)), bench.range(1) != 0));
}

// The same fall without the impacts held inside the implicit solve and with spheres fixed on the
// curve (docs/impacts.md): what holding them costs or saves, now that BM_FallWhole
// holds them (the scene's default).
void BM_FallWholeLimiterOnly(benchmark::State& bench) {
  ModelParams params = FallParams(static_cast<int>(bench.range(0)), true);
  params.contacts.impact_constraints = false;
  params.contacts.spheres_follow_material = false;
  RunFallWhole(bench, params);
}

void BM_FallSettled(benchmark::State& bench) {
  const Model model(FallParams(static_cast<int>(bench.range(0)), bench.range(1) != 0));
  Workspace workspace(model);
  State state = InitialState(model);
  const int64_t warmup_steps = static_cast<int64_t>(kWarmupSeconds * model.params().rate_hz + 0.5);
  for (int64_t i = 0; i < warmup_steps; ++i) Step(model, {}, &state, &workspace);
  const int64_t resets_before = state.nonfinite_resets;

  Tally tally;
  for (auto _ : bench) {
    Step(model, {}, &state, &workspace);
    tally.Add(state);
  }
  Report(bench, model, workspace.interactions()->chain().size(), tally, state.nonfinite_resets,
         workspace);
  bench.counters["warmup_resets"] = static_cast<double>(resets_before);
}

void BM_CavityClearing(benchmark::State& bench) {
  const Model model(
      SceneAtRate(VISCERA_SOURCE_DIR "/scenes/cavity.toml", static_cast<double>(bench.range(0))));
  Workspace workspace(model);
  const State start = InitialState(model);
  std::vector<double> costs_us;
  Tally tally;
  double peak = 0.0;
  int64_t resets = 0;
  for (auto _ : bench) {
    bench.PauseTiming();
    script::ScriptedTools scripted(
        model, script::ToolScript::Load(VISCERA_SOURCE_DIR "/scenes/clearing.csv"));
    const int64_t steps = static_cast<int64_t>(scripted.duration() * model.params().rate_hz + 0.5);
    costs_us.reserve(costs_us.size() + static_cast<size_t>(steps));
    State state = start;
    bench.ResumeTiming();
    for (int64_t i = 0; i < steps; ++i) {
      // The script's targets (aimed rows against the tube as it is): the device's work, not timed.
      bench.PauseTiming();
      const std::span<const ToolTarget> targets =
          scripted.At(state.t + model.step_size(), workspace.interactions());
      bench.ResumeTiming();
      const int64_t begin = ThreadCpuNanos();
      Step(model, {{}, targets}, &state, &workspace);
      costs_us.push_back(static_cast<double>(ThreadCpuNanos() - begin) * 1e-3);
      tally.Add(state);
      for (const ToolState& t : state.tools) peak = std::max(peak, t.force.norm());
    }
    resets += state.nonfinite_resets;
  }
  Report(bench, model, workspace.interactions()->chain().size(), tally, resets, workspace);
  bench.counters["p99_us"] = Quantile(costs_us, 0.99);
  bench.counters["deepest_pct_r"] = 100.0 * tally.deepest / model.params().radius;
  bench.counters["peak_force"] = peak;
}

// pybullet's capsule chain on the peers' benchmark, CPU seconds per simulated second: the
// requirements' table of peers (viscera 0.063 s, 39x faster). The fastest peer; MuJoCo's flex
// rod took 230x.
constexpr double kPybulletSecondsPerSimulatedSecond = 0.063 * 39.0;

void BM_PaperCoilFall(benchmark::State& bench) {
  const Model model(SceneAtRate(VISCERA_SOURCE_DIR "/bench/scenes/paper_coil.toml",
                                static_cast<double>(bench.range(0))));
  Workspace workspace(model);
  const State start = InitialState(model);
  const int64_t steps = static_cast<int64_t>(2.0 * model.params().rate_hz + 0.5);
  State state = start;
  Step(model, {}, &state,
       &workspace);  // warm-up: the solvers and the contact buffers size themselves
  Tally tally;
  double end = 0.0;
  int64_t resets = 0;
  for (auto _ : bench) {
    bench.PauseTiming();
    state = start;  // same sizes: a copy, no allocation
    bench.ResumeTiming();
    for (int64_t i = 0; i < steps; ++i) {
      Step(model, {}, &state, &workspace);
      tally.Add(state);
    }
    const double clearance = state.contacts.min_clearance;
    end = std::isnan(clearance) ? 0.0 : std::max(0.0, -clearance);
    resets += state.nonfinite_resets;
  }
  Report(bench, model, workspace.interactions()->chain().size(), tally, resets, workspace);
  const double radius = model.params().radius;
  bench.counters["deepest_pct_r"] = 100.0 * tally.deepest / radius;
  bench.counters["deepest_at_s"] = tally.deepest_at;
  bench.counters["end_pct_r"] = 100.0 * end / radius;
  using C = benchmark::Counter;
  bench.counters["x_pybullet"] =
      C(static_cast<double>(tally.steps) * model.step_size() * kPybulletSecondsPerSimulatedSecond,
        C::kIsRate);
}

void BM_CavityMesentery(benchmark::State& bench) {
  const scene::Scene scene = scene::LoadSceneFile(VISCERA_SOURCE_DIR "/scenes/cavity.toml");
  const Model model(scene.model);
  Workspace workspace(model);
  State state = InitialState(model);
  if (bench.range(0) == 0) {
    for (auto _ : bench) Step(model, {}, &state, &workspace);
    return;
  }
  // every tether taut: slack lengths shortened below the settled distances
  std::vector<Tether> tethers = model.tethers();
  for (Tether& t : tethers) t.length = 0.5 * (Model::Evaluate(t.at, state.q) - t.root).norm();
  Points f = Points::Zero(model.num_points(), 3);
  BlockBand k(model.num_points()), d(model.num_points());
  for (auto _ : bench) {
    for (int sub = 0; sub < model.params().substeps; ++sub) {
      benchmark::DoNotOptimize(AddMesenteryForces(tethers, state.q, state.qd, &f, &k, &d));
    }
    benchmark::ClobberMemory();
  }
}

void Sizes(benchmark::internal::Benchmark* b) {
  for (int self : {1, 0}) {
    for (int n : {50, 125, 250, 500, 1000}) b->Args({n, self});
  }
}

BENCHMARK(BM_FallWhole)->Apply(Sizes)->ArgNames({"n", "self"})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FallWholeLimiterOnly)->Arg(250)->ArgNames({"n"})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FallSettled)->Apply(Sizes)->ArgNames({"n", "self"})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PaperCoilFall)->Arg(100)->Arg(1000)->ArgNames({"rate"})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CavityMesentery)->Arg(0)->Arg(1)->ArgNames({"term"})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CavityClearing)
    ->Arg(100)
    ->Arg(1000)
    ->ArgNames({"rate"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace viscera::mechanics

BENCHMARK_MAIN();
