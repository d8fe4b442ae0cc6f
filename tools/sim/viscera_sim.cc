// viscera-sim: runs a scene offline, with no network, and reports what happened.
//   viscera-sim SCENE.toml --duration SECONDS [--trace FILE.jsonl] [--trace-every N] [--json]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <vector>

#include "common/check.h"
#include "common/clock.h"
#include "mechanics/stability.h"
#include "mechanics/step.h"
#include "scene/scene.h"
#include "sim/progress_bar.h"
#include "sim/trace_writer.h"

namespace viscera::tools {
namespace {

using mechanics::Energies;
using mechanics::State;

struct Options {
  std::string scene;
  double duration = 1.0;
  std::string trace;
  int trace_every = 1;
  bool json = false;
};

Vec3 CentreOfMass(const mechanics::Model& model, const Points& q) {
  // Mass-weighted mean of the control points with the gravity weights m integral b_i ds.
  const Points& w = model.gravity_force();
  VecX weights(model.num_points());
  for (int i = 0; i < model.num_points(); ++i) weights(i) = 1.0;
  if (model.params().gravity.norm() > 0.0) weights = w * model.params().gravity / model.params().gravity.squaredNorm();
  return (q.transpose() * weights) / weights.sum();
}

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(std::ceil(p * v.size())) - (p > 0 ? 1 : 0));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

int Run(const Options& opt) {
  scene::Scene scene = scene::LoadSceneFile(opt.scene);
  for (const std::string& w : scene.warnings) std::cerr << "warning: " << opt.scene << ": " << w << std::endl;
  const mechanics::Model model = [&] {
    try {
      return mechanics::Model(scene.model);
    } catch (const InputError& e) {
      Fail(opt.scene, ": ", e.what());
    }
  }();
  ThrowUnless(opt.duration > 0.0 && std::isfinite(opt.duration), "--duration ", opt.duration, ": must be > 0");
  ThrowUnless(opt.trace_every >= 1, "--trace-every ", opt.trace_every, ": must be >= 1");

  State state = mechanics::InitialState(model);
  if (model.params().integrator == mechanics::IntegratorKind::kRk4) {
    const mechanics::StabilityEstimate est = mechanics::EstimateStability(model, state);
    if (!est.stable()) {
      std::cerr << "warning: RK4 step beyond its stability limit: h * omega_max = " << est.h_times_rate
                << " > " << mechanics::kRk4StabilityLimit << " (h = " << model.substep_size()
                << " s, omega_max = " << est.rate_max << " 1/s); set [simulation] substeps >= "
                << est.stable_substeps << " or integrator = \"implicit\"\n";
    }
  }

  std::unique_ptr<TraceWriter> trace;
  if (!opt.trace.empty()) trace = std::make_unique<TraceWriter>(opt.trace);
  const spline::CatmullRom& curve = model.curve();
  auto record = [&](double step_us) {
    if (trace) trace->Write(state, curve.Length(state.q), mechanics::ComputeEnergies(model, state.q, state.qd), step_us);
  };

  const Energies e0 = mechanics::ComputeEnergies(model, state.q, state.qd);
  const Vec3 com0 = CentreOfMass(model, state.q);
  record(0.0);
  const int64_t steps = std::max<int64_t>(1, std::llround(opt.duration * model.params().rate_hz));
  std::vector<double> cost_us;
  cost_us.reserve(static_cast<size_t>(steps));
  mechanics::Workspace workspace(model);
  ProgressBar progress(steps);
  for (int64_t k = 1; k <= steps; ++k) {
    const int64_t begin = ThreadCpuNanos();
    mechanics::Step(model, {}, &state, &workspace);
    const double us = (ThreadCpuNanos() - begin) * 1e-3;
    cost_us.push_back(us);
    if (k % opt.trace_every == 0 || k == steps) record(us);
    progress.Update(k);
  }

  const Energies e = mechanics::ComputeEnergies(model, state.q, state.qd);
  const Vec3 com = CentreOfMass(model, state.q);
  double total_us = 0.0;
  for (double c : cost_us) total_us += c;
  const double simulated = state.t;
  nlohmann::json summary = {
      {"scene", opt.scene},
      {"control_points", model.num_points()},
      {"integrator", model.params().integrator == mechanics::IntegratorKind::kRk4 ? "rk4" : "implicit"},
      {"rate_hz", model.params().rate_hz},
      {"substeps", model.params().substeps},
      {"frames", trace ? trace->frames() : 0},
      {"steps", steps},
      {"simulated_seconds", simulated},
      {"step_cost_us", {{"mean", total_us / steps}, {"p99", Percentile(cost_us, 0.99)}, {"max", *std::max_element(cost_us.begin(), cost_us.end())}}},
      {"realtime_factor", simulated / (total_us * 1e-6)},
      {"initial_energy", e0.total()},
      {"final_energy", {{"kinetic", e.kinetic}, {"gravity", e.gravity}, {"stretch", e.stretch}, {"bend", e.bend}, {"continuous", e.continuous}, {"attachment", e.attachment}, {"total", e.total()}}},
      {"rest_length", model.params().length},
      {"final_length", curve.Length(state.q)},
      {"centre_of_mass_start", {com0.x(), com0.y(), com0.z()}},
      {"centre_of_mass_end", {com.x(), com.y(), com.z()}},
      {"nonfinite_resets", state.nonfinite_resets},
  };
  if (opt.json) {
    std::cout << summary.dump(2) << "\n";
    return 0;
  }
  std::printf("scene            %s (%d control points, %s, %g Hz x %d sub-steps)\n", opt.scene.c_str(),
              model.num_points(), summary["integrator"].get<std::string>().c_str(), model.params().rate_hz,
              model.params().substeps);
  std::printf("simulated        %.3f s in %lld steps, %d trace frames%s%s\n", simulated,
              static_cast<long long>(steps), trace ? trace->frames() : 0, trace ? " -> " : "",
              opt.trace.c_str());
  std::printf("step cost        mean %.1f us, p99 %.1f us  (%.0fx real time on one core)\n",
              total_us / steps, Percentile(cost_us, 0.99), simulated / (total_us * 1e-6));
  std::printf("centre of mass   z %.4f m -> %.4f m", com0.z(), com.z());
  if (model.pins().empty() && model.attachments().empty()) {
    // A free body: its centre of mass falls like a point with viscous friction gamma.
    const double gamma = model.params().damping, g = model.params().gravity.z(), t = simulated;
    const double expected = gamma > 0.0 ? g / gamma * (t - (1.0 - std::exp(-gamma * t)) / gamma) : 0.5 * g * t * t;
    std::printf(" (point under gravity and viscous friction: %.4f m)", com0.z() + expected);
  }
  std::printf("\n");
  std::printf("length           rest %.4f m, final %.4f m (%+.2f %%)\n", model.params().length,
              curve.Length(state.q), 100.0 * (curve.Length(state.q) / model.params().length - 1.0));
  std::printf("energy           %.4f J -> %.4f J (kinetic %.4f, gravity %.4f, stretch %.4f, bend %.4f, continuous %.4f)\n",
              e0.total(), e.total(), e.kinetic, e.gravity, e.stretch, e.bend, e.continuous);
  if (state.nonfinite_resets > 0) {
    std::printf("WARNING          %lld non-finite steps were reset\n", static_cast<long long>(state.nonfinite_resets));
  }
  return 0;
}

}  // namespace
}  // namespace viscera::tools

int main(int argc, char** argv) {
  viscera::tools::Options opt;
  CLI::App app{"viscera-sim: run a viscera scene offline and report what happened"};
  app.add_option("scene", opt.scene, "scene file (TOML)")->required();
  app.add_option("--duration", opt.duration, "simulated seconds")->capture_default_str();
  app.add_option("--trace", opt.trace, "write a JSON Lines trace to this file");
  app.add_option("--trace-every", opt.trace_every, "record every N-th step")->capture_default_str();
  app.add_flag("--json", opt.json, "print the final summary as JSON");
  CLI11_PARSE(app, argc, argv);
  try {
    return viscera::tools::Run(opt);
  } catch (const viscera::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  }
}
