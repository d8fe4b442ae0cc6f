// Would a direct solver of the coupled pairs beat the step's CG? (the exact coupling of self
// pairs; figures and the command in docs/benchmarks.md, "Direct solvers of the coupled pairs";
// what they mean in docs/self-coupling.md, "Why CG and not the alternatives").
//
// Runs the scenes of the contact cost rows (docs/self-coupling.md, "What the coupling costs"),
// sub-step by sub-step as mechanics::Step does (and checks at the end that Step's own run
// reaches the same state bit for bit), and after every implicit sub-step takes the exact matrix
// A = A_s + w u u^T of that sub-step (exact_system.h):
//   sweep      every sub-step: the pairs, whether the pattern of A_s changed since the last
//              sub-step, the step's CG iterations, and the cost of each way to solve A x = b:
//                cg      the step's way: the band factor, its column solves (b, and u for the
//                        rank-one term), then (iterations + 1) CG iterations (a product with A
//                        and a band solve each; the +1 is the start's residual)
//                direct  CHOLMOD on A_s (AMD, simplicial LL'): numeric factorization, a solve
//                        of b and of u (Sherman-Morrison), plus the symbolic analysis whenever
//                        the pattern changed since the last sub-step
//                IC      incomplete Cholesky of A_s (incomplete_cholesky.h: Eigen's ICT, natural
//                        or AMD order, 0/5/20 entries of fill per column) as CG's preconditioner
//                        in place of the band's: CG on the step's own product, from the step's
//                        own warm start (the band's answer plus the extrapolated correction) and
//                        to the step's own stop (on r^T M^-1 r, M now the IC); its cost is the
//                        factorization (ordering, factor, the solve of u) and (iterations + 1)
//                        iterations (a product and the IC's solves each). The warm start's band
//                        solve is not charged to it (optimistic for IC).
//              Each operation is timed as the median of 3 calls (thread CPU time), the
//              methods back to back on the same sub-step. The direct answer's residual in the
//              step's own product (MultiplyExact) is checked at every sub-step, and so is the
//              warm start: CG with the band preconditioner from it must take the step's iterations.
//   snapshots  at named moments: every ordering (natural, AMD, METIS, NESDIS) simplicial and
//              supernodal: analysis time, nnz(L), flops, numeric factorization, solve; the
//              band's factor and solve and one CG iteration for comparison; Woodbury's parts
//              (one band solve per rank of the pairs, a dense factorization of that order);
//              each IC variant's nnz(L), factorization, iteration and iterations.
//              Rounds alternate the methods; medians over the rounds.
// Usage: bench_direct_coupling [case ...]   (cases: cavity100 cavity1k fall coil; default all)
#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>

#include "common/check.h"
#include "common/clock.h"
#include "common/quantile.h"
#include "exact_system.h"
#include "fall_scene.h"
#include "incomplete_cholesky.h"
#include "mechanics/implicit_system_view.h"
#include "mechanics/step.h"
#include "scene/scene.h"
#include "script/scripted_tools.h"

namespace viscera::bench {
namespace {

using mechanics::ImplicitEulerIntegrator;
using mechanics::ImplicitSystemView;
using mechanics::Interactions;
using mechanics::Model;
using mechanics::State;

template <class F>
double MedianMicros(int calls, F&& f) {
  std::vector<double> us(calls);
  for (double& t : us) {
    const int64_t begin = ThreadCpuNanos();
    f();
    t = static_cast<double>(ThreadCpuNanos() - begin) * 1e-3;
  }
  return Quantile(us, 0.5);
}

struct Case {
  std::string name;
  mechanics::ModelParams params;
  const char* script;  // tool script, or nullptr
  double seconds;
  std::vector<std::pair<std::string, double>> snapshots;  // (name, simulated time)
};

std::vector<Case> Cases() {
  const char* cavity = VISCERA_SOURCE_DIR "/scenes/cavity.toml";
  const char* clearing = VISCERA_SOURCE_DIR "/scenes/clearing.csv";
  return {
      {"cavity100",
       SceneAtRate(cavity, 100),
       clearing,
       5.5,
       {{"cavity 100 Hz, t=1.5 s", 1.5}, {"cavity 100 Hz, t=3.5 s", 3.5}}},
      {"cavity1k", SceneAtRate(cavity, 1000), clearing, 5.5, {{"cavity 1 kHz, t=3.5 s", 3.5}}},
      {"fall",
       FallParams(250),
       nullptr,
       3.0,
       {{"fall, impact t=0.3 s", 0.3}, {"fall, settled t=2.9 s", 2.9}}},
      {"coil",
       SceneAtRate(VISCERA_SOURCE_DIR "/bench/scenes/paper_coil.toml", 100),
       nullptr,
       2.0,
       {{"coil, landing t=0.4 s", 0.4}}},
  };
}

// After each implicit sub-step: the step's integrator and interactions, and the step's time.
using Observer =
    std::function<void(ImplicitEulerIntegrator&, Interactions&, const State&, double t)>;

// Steps the case as mechanics::Step does (step.cc), calling `observe` after every sub-step, then
// runs it again through Step and demands the same end state, bit for bit.
void Run(const Case& c, const Observer& observe) {
  const Model model(c.params);
  VISCERA_DEMAND(model.pins().empty());  // exact_system.h: no Schur complement for pins
  Interactions interactions(model);
  ImplicitEulerIntegrator integrator(model, &interactions);
  Interactions* reference_interactions = nullptr;
  auto run = [&](const std::function<void(const mechanics::StepInputs&, State*)>& step) {
    std::optional<script::ScriptedTools> scripted;
    if (c.script) scripted.emplace(model, script::ToolScript::Load(c.script));
    State state = InitialState(model);
    const int64_t steps = std::llround(c.seconds * model.params().rate_hz);
    for (int64_t i = 0; i < steps; ++i) {
      const double t = state.t + model.step_size();
      Interactions* aiming = reference_interactions ? reference_interactions : &interactions;
      const auto targets =
          scripted ? scripted->At(t, aiming) : std::span<const mechanics::ToolTarget>{};
      step({{}, targets}, &state);
    }
    return state;
  };
  const State observed = run([&](const mechanics::StepInputs& inputs, State* state) {
    const int substeps = interactions.RequiredSubsteps(state);
    const double h = model.step_size() / substeps;
    for (int k = 0; k < substeps; ++k) {
      interactions.BeginSubstep(k == 0 ? inputs.tools : std::span<const mechanics::ToolTarget>{}, h,
                                state);
      integrator.Advance(inputs.loads, h, state);
      observe(integrator, interactions, *state, state->t + model.step_size());
    }
    state->substeps = substeps;
    ++state->steps;
    state->t = state->steps * model.step_size();
    VISCERA_DEMAND(state->q.allFinite() && state->qd.allFinite());
    interactions.EndStep(state);
  });
  mechanics::Workspace workspace(model);
  reference_interactions = workspace.interactions();
  const State reference = run([&](const mechanics::StepInputs& inputs, State* state) {
    mechanics::Step(model, inputs, state, &workspace);
  });
  ThrowUnless(reference.q == observed.q && reference.qd == observed.qd, c.name,
              ": the observed run left Step's trajectory");
}

// The incomplete Cholesky variants measured.
struct IcVariant {
  IcOrdering ordering;
  int fill;
};
const IcVariant kIcVariants[] = {{IcOrdering::kNatural, 0},  {IcOrdering::kNatural, 5},
                                 {IcOrdering::kNatural, 20}, {IcOrdering::kAmd, 0},
                                 {IcOrdering::kAmd, 5},      {IcOrdering::kAmd, 20}};
constexpr int kIcMaxIterations = 500;  // well past the step's 60: how many it would need

struct IcSweep {
  std::string name;
  int64_t iterations = 0, unconverged = 0, failures = 0;
  double nonzeros = 0.0, flops = 0.0, factor_us = 0.0, iteration_us = 0.0, total_us = 0.0,
         cg_us = 0.0;
  double iterating_us = 0.0;  // (iterations + 1) iterations: IC's cost with a free factorization
  double worst_band_residual = 0.0;  // r^T P^-1 r / stop at IC's exit, P the band preconditioner
};

// Sweep over every sub-step.
struct Sweep {
  int64_t substeps = 0, coupled = 0, pairs = 0, cg_iterations = 0;
  int64_t pattern_changes = 0;  // pattern of A_s differs from the last sub-step's
  int64_t outgrown = 0;         // not inside the last analysed pattern (analyse only then)
  double cg_us = 0.0, direct_us = 0.0, direct_outgrown_us = 0.0, analysis_us = 0.0;
  double worst_residual = 0.0;
  std::vector<std::pair<int, int>> last_blocks, analysed_blocks;
  // The step's warm start: the correction it extrapolates for the next sub-step, and this one's.
  VecX next_extrapolated, extrapolated;
  int64_t start_mismatches =
      0;  // band CG from the rebuilt start took other than the step's iterations
  std::vector<IcSweep> ic;
};

// IC in place of the band preconditioner on one sub-step, from the step's start to its stop.
struct IcRun {
  bool factored = false;
  int iterations = 0;
  double nonzeros = 0.0, flops = 0.0, factor_us = 0.0, iteration_us = 0.0, band_residual = 0.0;
};

// The step's CG start on this sub-step and its residual b - A x.
struct CgStart {
  VecX x, r;
};
CgStart StepStart(const ImplicitSystemView& system, const BandPreconditioner& band,
                  const VecX& extrapolated) {
  CgStart start{CgWarmStart(band, system.last_rhs(), extrapolated), {}};
  system.MultiplyExact(start.x, &start.r);
  start.r = system.last_rhs() - start.r;
  return start;
}

IcRun RunIc(const IcVariant& v, const ImplicitSystemView& system, const SparseUpper& a,
            const BandPreconditioner& band, const CgStart& start) {
  const double w = system.rank_one_weight();
  const VecX u = Eigen::Map<const VecX>(system.rank_one_u().data(), a.n);
  IncompleteCholeskyPreconditioner ic(v.ordering, v.fill);
  IcRun run;
  run.factor_us = MedianMicros(3, [&] { run.factored = ic.Factor(a, w, u); });
  if (!run.factored) return run;
  run.nonzeros = static_cast<double>(ic.factor_nonzeros());
  run.flops = ic.factor_flops();
  VecX x = start.x, r = start.r;
  run.iterations = ContinueCg(system, ic, system.last_cg_stop(), 0.0, kIcMaxIterations, &x, &r);
  VecX z = r;
  band.Apply(&z);
  run.band_residual = r.dot(z) / system.last_cg_stop();
  constexpr int kTimedIterations = 8;
  VecX cg_x;
  run.iteration_us =
      MedianMicros(
          3, [&] { SolveByCg(system, ic, system.last_rhs(), 0.0, kTimedIterations, &cg_x); }) /
      kTimedIterations;
  return run;
}

void ObserveSweep(ImplicitEulerIntegrator& integrator, Interactions& interactions,
                  const State& state, Sweep* s) {
  const ImplicitSystemView system(integrator);
  ++s->substeps;
  const Eigen::Index n = system.last_rhs().size();  // the step starts with no correction
  s->extrapolated = s->next_extrapolated.size() == n ? s->next_extrapolated : VecX::Zero(n);
  s->next_extrapolated = 2.0 * state.cg_correction - state.cg_previous_correction;
  const int pairs = interactions.coupled_pairs();
  if (pairs == 0) {
    s->last_blocks.clear();
    return;
  }
  ++s->coupled;
  s->pairs += pairs;
  const int cg = integrator.last_cg_iterations();
  s->cg_iterations += cg;
  const SparseUpper a = AssembleExact(system, interactions);
  const std::vector<std::pair<int, int>> blocks = CoupledBlocks(a);
  const bool changed = blocks != s->last_blocks;
  const bool outgrown = !std::includes(s->analysed_blocks.begin(), s->analysed_blocks.end(),
                                       blocks.begin(), blocks.end());
  s->pattern_changes += changed;
  s->outgrown += outgrown;
  if (outgrown) s->analysed_blocks = blocks;
  s->last_blocks = blocks;

  const double w = system.rank_one_weight();
  const VecX u = Eigen::Map<const VecX>(system.rank_one_u().data(), a.n);
  const VecX& b = system.last_rhs();
  const int columns = w > 0.0 ? 2 : 1;
  mechanics::CholmodCommon common;
  DirectSolver direct(&common, Ordering::kAmd, /*supernodal=*/false);
  BandPreconditioner band(system);
  mechanics::BlockBandCholesky factor;
  VecX x = b, z(a.n), cg_x(a.n);
  const double analysis = MedianMicros(3, [&] { direct.Analyze(a); });
  const double numeric = MedianMicros(3, [&] { VISCERA_DEMAND(direct.Factorize(a)); });
  const double solve = MedianMicros(3, [&] {
    x = b;
    direct.Solve(&x);
  });
  const double band_factor =
      MedianMicros(3, [&] { VISCERA_DEMAND(factor.Factor(system.band_system())); });
  const double band_solve = MedianMicros(3, [&] {
    x = b;
    factor.SolveInPlace(x.data());
  });
  constexpr int kTimedIterations = 8;
  const double iteration =
      MedianMicros(3, [&] { SolveByCg(system, band, b, 0.0, kTimedIterations, &cg_x); }) /
      kTimedIterations;
  const double cg_path = band_factor + columns * band_solve + (cg + 1) * iteration;
  s->cg_us += cg_path;
  s->direct_us += numeric + columns * solve + (changed ? analysis : 0.0);
  s->direct_outgrown_us += numeric + columns * solve + (outgrown ? analysis : 0.0);
  s->analysis_us += analysis;
  // The direct answer solves the step's own exact system.
  x = b;
  direct.SolveWithRankOne(w, u, &x, &z);
  VecX ax;
  system.MultiplyExact(x, &ax);
  s->worst_residual = std::max(s->worst_residual, (ax - b).norm() / b.norm());

  // The step's start, checked by rerunning the step's CG from it; then each IC from it.
  const CgStart start = StepStart(system, band, s->extrapolated);
  {
    VecX x_again = start.x, r_again = start.r;
    const int again = ContinueCg(system, band, system.last_cg_stop(), 0.0,
                                 ImplicitEulerIntegrator::kMaxCgIterations, &x_again, &r_again);
    s->start_mismatches += again != cg;
  }
  if (s->ic.empty()) {
    for (const IcVariant& v : kIcVariants)
      s->ic.push_back({IncompleteCholeskyPreconditioner(v.ordering, v.fill).name()});
  }
  for (size_t i = 0; i < std::size(kIcVariants); ++i) {
    const IcRun run = RunIc(kIcVariants[i], system, a, band, start);
    IcSweep& ic = s->ic[i];
    if (!run.factored) {
      ++ic.failures;
      continue;
    }
    ic.iterations += run.iterations;
    ic.unconverged += run.iterations == kIcMaxIterations;
    ic.nonzeros += run.nonzeros;
    ic.flops += run.flops;
    ic.iterating_us += (run.iterations + 1) * run.iteration_us;
    ic.factor_us += run.factor_us;
    ic.iteration_us += run.iteration_us;
    ic.total_us += run.factor_us + (run.iterations + 1) * run.iteration_us;
    ic.cg_us += cg_path;
    ic.worst_band_residual = std::max(ic.worst_band_residual, run.band_residual);
  }
}

void PrintSweep(const Case& c, const Sweep& s) {
  const double coupled = static_cast<double>(std::max<int64_t>(1, s.coupled));
  std::printf(
      "%-10s sub-steps %lld, coupled %lld, pairs %.0f, CG it %.2f | pattern changed %.1f %%, "
      "outgrew the analysed "
      "%.1f %% | per coupled sub-step: CG path %.1f us, direct %.1f us (analysis on outgrowth: "
      "%.1f us; "
      "analysis alone %.1f us) | direct/CG %.2f | worst residual %.1e\n",
      c.name.c_str(), static_cast<long long>(s.substeps), static_cast<long long>(s.coupled),
      s.pairs / coupled, static_cast<double>(s.cg_iterations) / coupled,
      100.0 * static_cast<double>(s.pattern_changes) / coupled,
      100.0 * static_cast<double>(s.outgrown) / coupled, s.cg_us / coupled, s.direct_us / coupled,
      s.direct_outgrown_us / coupled, s.analysis_us / coupled, s.direct_us / s.cg_us,
      s.worst_residual);
  std::printf(
      "  warm start rebuilt: band CG took the step's iterations on %lld of %lld coupled "
      "sub-steps\n",
      static_cast<long long>(s.coupled - s.start_mismatches), static_cast<long long>(s.coupled));
  std::printf("  %-14s %8s %7s %9s %8s %12s %10s %8s %7s %13s %6s %12s\n", "preconditioner",
              "nnz(L)", "Mflop", "factor_us", "CG it", "iteration_us", "total_us", "CG path", "/CG",
              "iterating/CG", "fails", "band r/stop");
  for (const IcSweep& ic : s.ic) {
    const double factored = static_cast<double>(std::max<int64_t>(1, s.coupled - ic.failures));
    std::printf("  %-14s %8.0f %7.3f %9.1f %8.2f %12.2f %10.1f %8.1f %7.2f %13.2f %6lld %12.2f%s\n",
                ic.name.c_str(), ic.nonzeros / factored, ic.flops / factored * 1e-6,
                ic.factor_us / factored, static_cast<double>(ic.iterations) / factored,
                ic.iteration_us / factored, ic.total_us / factored, ic.cg_us / factored,
                ic.total_us / ic.cg_us, ic.iterating_us / ic.cg_us,
                static_cast<long long>(ic.failures), ic.worst_band_residual,
                ic.unconverged > 0
                    ? (" (" + std::to_string(ic.unconverged) + " unconverged)").c_str()
                    : "");
  }
  std::fflush(stdout);
}

// One snapshot in detail: every ordering, both factorizations, the band, Woodbury's parts.
void Snapshot(const std::string& name, ImplicitEulerIntegrator& integrator,
              Interactions& interactions, const VecX& extrapolated) {
  const ImplicitSystemView system(integrator);
  const SparseUpper a = AssembleExact(system, interactions);
  const int pairs = interactions.coupled_pairs();
  const VecX& b = system.last_rhs();
  // The assembled matrix is the step's product.
  const double w = system.rank_one_weight();
  const VecX u = Eigen::Map<const VecX>(system.rank_one_u().data(), a.n);
  const VecX probe = VecX::Random(a.n);
  VecX mine, theirs;
  MultiplySymmetric(a, w, u, probe, &mine);
  system.MultiplyExact(probe, &theirs);
  const double mismatch = (mine - theirs).norm() / theirs.norm();
  VISCERA_DEMAND(mismatch < 1e-12);
  std::printf(
      "\n%s: 3N = %d, pairs %d, CG iterations %d, nnz(A_s upper) %lld (band %d), off-band blocks "
      "%zu, "
      "|A x - MultiplyExact x| / |.| = %.1e\n",
      name.c_str(), a.n, pairs, integrator.last_cg_iterations(),
      static_cast<long long>(a.nonzeros()),
      a.col_ptr[a.n] - static_cast<int>(9 * CoupledBlocks(a).size()), CoupledBlocks(a).size(),
      mismatch);

  struct Row {
    Ordering ordering;
    bool supernodal;
    std::vector<double> analyse, factor, solve;
    double lnz = 0.0, flops = 0.0;
  };
  std::vector<Row> rows;
  for (bool super : {false, true}) {
    for (Ordering o : {Ordering::kNatural, Ordering::kAmd, Ordering::kMetis, Ordering::kNesdis})
      rows.push_back(Row{o, super, {}, {}, {}});
  }
  std::vector<double> band_factor, band_solve, iteration, woodbury_dense;
  mechanics::CholmodCommon common;
  BandPreconditioner band(system);
  mechanics::BlockBandCholesky factor;
  VecX x(a.n), cg_x(a.n);
  // Woodbury: A_s = P - V V^T with one column of V per rank of a pair's 3x3 (1 to 3): one band
  // solve per column, then the capacitance I - V^T P^-1 V (order 3 x pairs at most) factored.
  const int capacitance = 3 * pairs;
  Eigen::MatrixXd spd = Eigen::MatrixXd::Random(capacitance, capacitance);
  spd = spd * spd.transpose() + capacitance * Eigen::MatrixXd::Identity(capacitance, capacitance);
  Eigen::LLT<Eigen::MatrixXd> llt(capacitance);
  constexpr int kRounds = 5;
  for (int round = 0; round < kRounds; ++round) {
    for (Row& r : rows) {
      DirectSolver direct(&common, r.ordering, r.supernodal);
      r.analyse.push_back(MedianMicros(1, [&] { direct.Analyze(a); }));
      r.lnz = direct.factor_nonzeros();
      r.flops = direct.factor_flops();
      r.factor.push_back(MedianMicros(3, [&] { VISCERA_DEMAND(direct.Factorize(a)); }));
      r.solve.push_back(MedianMicros(3, [&] {
        x = b;
        direct.Solve(&x);
      }));
    }
    band_factor.push_back(
        MedianMicros(3, [&] { VISCERA_DEMAND(factor.Factor(system.band_system())); }));
    band_solve.push_back(MedianMicros(3, [&] {
      x = b;
      factor.SolveInPlace(x.data());
    }));
    iteration.push_back(MedianMicros(3, [&] { SolveByCg(system, band, b, 0.0, 8, &cg_x); }) / 8.0);
    woodbury_dense.push_back(MedianMicros(1, [&] { llt.compute(spd); }));
  }
  std::printf("  %-8s %-11s %10s %9s %10s %10s %9s\n", "ordering", "factor", "analyse_us", "nnz(L)",
              "Mflop", "numeric_us", "solve_us");
  for (const Row& r : rows) {
    std::printf("  %-8s %-11s %10.1f %9.0f %10.3f %10.1f %9.1f\n", OrderingName(r.ordering),
                r.supernodal ? "supernodal" : "simplicial", Quantile(r.analyse, 0.5), r.lnz,
                r.flops * 1e-6, Quantile(r.factor, 0.5), Quantile(r.solve, 0.5));
  }
  const double bf = Quantile(band_factor, 0.5), bs = Quantile(band_solve, 0.5),
               it = Quantile(iteration, 0.5);
  const int cg = integrator.last_cg_iterations(), columns = w > 0.0 ? 2 : 1;
  std::printf(
      "  band: factor %.1f us, solve %.1f us, CG iteration %.1f us; this sub-step's CG path %.1f "
      "us\n",
      bf, bs, it, bf + columns * bs + (cg + 1) * it);
  std::printf(
      "  Woodbury (rank %d to %d): %d to %d band solves %.0f to %.0f us, + dense LLT of order %d: "
      "%.0f us\n",
      pairs, capacitance, pairs, capacitance, pairs * bs, capacitance * bs, capacitance,
      Quantile(woodbury_dense, 0.5));
  // IC in place of the band preconditioner, from the step's start to its stop.
  const double level_zero = LevelZeroMultiplyAdds(a, false),
               band_part = LevelZeroMultiplyAdds(a, true);
  std::printf(
      "  level-0 IC, chain's order: %.0f multiply-adds, %.0f of them the band's (the band "
      "factor's: %.1f us)\n",
      level_zero, band_part, bf);
  const CgStart start = StepStart(system, band, extrapolated);
  for (const IcVariant& v : kIcVariants) {
    const IcRun run = RunIc(v, system, a, band, start);
    const std::string name = IncompleteCholeskyPreconditioner(v.ordering, v.fill).name();
    if (!run.factored) {
      std::printf("  %s: the factorization failed\n", name.c_str());
      continue;
    }
    std::printf(
        "  %s: nnz(L) %.0f, %.3f Mflop, factor %.1f us, %d CG iterations (the step's %d), "
        "iteration %.1f us, "
        "total %.1f us\n",
        name.c_str(), run.nonzeros, run.flops * 1e-6, run.factor_us, run.iterations, cg,
        run.iteration_us, run.factor_us + (run.iterations + 1) * run.iteration_us);
  }
  std::fflush(stdout);
}

int Main(int argc, char** argv) {
  std::vector<std::string> wanted(argv + 1, argv + argc);
  for (const Case& c : Cases()) {
    if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), c.name) == wanted.end())
      continue;
    Sweep sweep;
    size_t next_snapshot = 0;
    Run(c, [&](ImplicitEulerIntegrator& integrator, Interactions& interactions, const State& state,
               double t) {
      ObserveSweep(integrator, interactions, state, &sweep);
      while (next_snapshot < c.snapshots.size() && t >= c.snapshots[next_snapshot].second - 1e-9) {
        Snapshot(c.snapshots[next_snapshot++].first, integrator, interactions, sweep.extrapolated);
      }
    });
    PrintSweep(c, sweep);
  }
  return 0;
}

}  // namespace
}  // namespace viscera::bench

int main(int argc, char** argv) { return viscera::bench::Main(argc, argv); }
