// viscera-sim: runs a scene offline, with no network, and reports what happened.
//   viscera-sim SCENE.toml --duration SECONDS [--trace FILE.jsonl] [--trace-every N] [--json]
//               [--render DIR [--render-every N] [--camera EX EY EZ CX CY CZ] [--frame-size WxH]]
//               [--camera-script CAMERA.csv]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <vector>

#include "assessment/report.h"
#include "common/check.h"
#include "common/clock.h"
#include "common/quantile.h"
#include "mechanics/implicit_euler.h"
#include "mechanics/stability.h"
#include "mechanics/step.h"
#include "render/frame_renderer.h"
#include "render/jpeg_sequence.h"
#include "render/port_scope.h"
#include "scene/scene.h"
#include "script/camera_script.h"
#include "session/replay.h"
#include "sim/progress_bar.h"
#include "sim/scripted_run.h"
#include "sim/sim_assessment.h"
#include "sim/trace_writer.h"
#include "skin/skin.h"

namespace viscera::tools {
namespace {

using mechanics::Energies;
using mechanics::State;

struct Options {
  std::string scene;
  double duration = 1.0;
  double rate_hz = 0.0;  // 0: the scene's
  std::string trace;
  int trace_every = 1;
  bool json = false;
  std::string tool_script;
  std::string replay;  // a viscerad session record (LCM log)
  std::string skin = "parametric";
  std::string export_mesh;
  std::vector<double> focus;  // hybrid skin: focus centre (m); default the skeleton's centre
  double focus_radius = 0.1;
  std::string render_dir;      // JPEG frames of the run go here
  int render_every = 0;        // steps between frames; 0: about 25 frames per simulated second
  std::vector<double> camera;  // eye x y z, look-at x y z (m); default frames the skeleton
  std::string camera_script;   // the camera moved along a CSV (script::CameraScript)
  std::string frame_size = "640x480";
  int jpeg_quality = 85;
  std::string report;  // the assessment as JSON goes here
};

// The run's laparoscope: --camera, else the scene's [camera] scope or the framing of the starting
// pose (as viscerad shows a session whose client set no camera) for a frame of --frame-size.
render::Laparoscope RunScope(const Options& opt, const mechanics::ModelParams& params,
                             const Points& q0) {
  int width = 0, height = 0;
  render::ParseFrameSize(opt.frame_size, &width, &height);
  ThrowUnless(opt.camera.empty() || opt.camera.size() == 6, "--camera takes ex ey ez cx cy cz");
  if (opt.camera.size() == 6) {
    return render::LookAtLaparoscope(Vec3(opt.camera[0], opt.camera[1], opt.camera[2]),
                                     Vec3(opt.camera[3], opt.camera[4], opt.camera[5]));
  }
  return render::SceneLaparoscope(params, q0, width, height);
}

assessment::View ViewOf(const render::Laparoscope& scope, const Options& opt) {
  int width = 0, height = 0;
  render::ParseFrameSize(opt.frame_size, &width, &height);
  return {scope.eye.cast<double>(), scope.target.cast<double>(), scope.up.cast<double>(),
          scope.fov_y_degrees, static_cast<double>(width) / height};
}

// Prints the assessment (text) or adds it to the JSON summary, and writes --report.
void EmitAssessment(const Options& opt, const SimAssessment& a, const assessment::Report& report,
                    nlohmann::json* summary) {
  if (!opt.report.empty()) {
    std::ofstream out(opt.report);
    out << assessment::ToJson(report).dump(2) << "\n";
    ThrowUnless(out.good(), "--report ", opt.report, ": cannot write");
  }
  if (summary != nullptr) {
    (*summary)["assessment"] = assessment::ToJson(report);
    (*summary)["exposure_series"] = a.exposure_series();
    (*summary)["exposure_cost_us"] = {{"mean", a.exposure_mean_us()},
                                      {"max", a.exposure_max_us()},
                                      {"capsules_tested_max", a.max_capsules_tested()}};
    return;
  }
  std::printf("%s", assessment::FormatReport(report).c_str());
  if (!report.targets.empty()) {
    std::printf(
        "exposure cost    mean %.1f us, max %.1f us per evaluation (all targets; at most %d "
        "capsules after the cull)\n",
        a.exposure_mean_us(), a.exposure_max_us(), a.max_capsules_tested());
  }
}

// Renders frames of the run into a directory (frame_000000.jpg, ...), from the scene's
// framing camera or the one given.
class FrameWriter {
 public:
  FrameWriter(const Options& opt, const mechanics::Model& model, const render::Laparoscope& scope)
      : sequence_(opt.render_dir), scope_(scope) {
    render::FrameOptions options;
    render::ParseFrameSize(opt.frame_size, &options.width, &options.height);
    options.jpeg_quality = opt.jpeg_quality;
    options.skin = opt.skin;
    options.skin_options.hybrid.focus_radius = opt.focus_radius;
    renderer_ = std::make_unique<render::FrameRenderer>(model.params(), options);
  }
  void SetScope(const render::Laparoscope& scope) { scope_ = scope; }
  void Write(const State& state, std::vector<std::pair<double, double>> damage = {}) {
    renderer_->SetDamage(std::move(damage));
    renderer_->Render(state, scope_);
    sequence_.Write(renderer_->Encode());
    render_ms_ += renderer_->timings().skin_ms + renderer_->timings().render_ms +
                  renderer_->timings().encode_ms;
  }
  int frames() const { return sequence_.frames(); }
  double mean_ms() const { return frames() > 0 ? render_ms_ / frames() : 0.0; }

 private:
  render::JpegSequence sequence_;
  std::unique_ptr<render::FrameRenderer> renderer_;
  render::Laparoscope scope_;
  double render_ms_ = 0.0;
};

// Writes the skin of the final pose (OBJ or PLY by extension).
void ExportMesh(const Options& opt, const mechanics::Model& model, const Points& q) {
  skin::SkinOptions options;
  options.radius = model.params().radius;
  if (opt.focus.size() == 3) {
    options.hybrid.focus = Vec3(opt.focus[0], opt.focus[1], opt.focus[2]);
  } else {
    options.hybrid.focus = q.colwise().mean().transpose();
  }
  ThrowUnless(opt.focus.empty() || opt.focus.size() == 3, "--focus takes x,y,z");
  options.hybrid.focus_radius = opt.focus_radius;
  std::unique_ptr<skin::Skin> s = skin::MakeSkin(opt.skin, options);
  s->Bind(static_cast<int>(q.rows()));
  skin::Mesh mesh;
  s->Build(q, &mesh);
  skin::WriteMesh(opt.export_mesh, mesh);
  std::cerr << "mesh: " << opt.skin << " skin, " << s->stats().triangles << " triangles -> "
            << opt.export_mesh << std::endl;
}

// The tube's linear momentum and its tools' tips' (N s): what the hands' impulse is checked
// against (docs/tool-coupling.md).
Vec3 Momentum(const mechanics::Model& model, const mechanics::State& state) {
  Vec3 p = model.Momentum(state.qd);
  for (size_t t = 0; t < state.tools.size(); ++t)
    p += model.params().tools[t].mass * state.tools[t].tip_velocity;
  return p;
}

nlohmann::json Json(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

// Replays a viscerad session record: the same scene, inputs and steps, so the same trajectory.
int Replay(const Options& opt) {
  std::unique_ptr<TraceWriter> trace;
  if (!opt.trace.empty()) trace = std::make_unique<TraceWriter>(opt.trace);
  int64_t step = 0;
  std::unique_ptr<SimAssessment> assessed;  // made at the first step: the record holds the model
  const session::ReplayResult r = session::ReplayRecord(
      opt.replay, [&](const mechanics::Model& model, const mechanics::State& state) {
        if (!assessed)
          assessed = std::make_unique<SimAssessment>(
              model, ViewOf(RunScope(opt, model.params(), state.q), opt));
        assessed->AddStep(state);
        if (trace && step++ % opt.trace_every == 0) {
          trace->Write(model, state, nullptr, model.curve().Length(state.q),
                       mechanics::ComputeEnergies(model, state.q, state.qd), 0.0);
        }
      });
  nlohmann::json summary = {{"record", opt.replay},
                            {"session", r.session_id},
                            {"scene", r.scene},
                            {"rate_hz", r.rate_hz},
                            {"steps", r.steps},
                            {"resets", r.resets},
                            {"recoveries", r.recoveries},
                            {"skeletons_compared", r.skeletons_compared},
                            {"max_deviation", r.max_deviation},
                            {"forces_compared", r.forces_compared},
                            {"force_mismatches", r.force_mismatches},
                            {"first_force_mismatch", r.first_force_mismatch},
                            {"frames", trace ? trace->frames() : 0}};
  if (assessed) {
    assessment::Report report = assessed->Report(r.session_id, r.scene);
    report.sim_time = r.final_state.t;
    EmitAssessment(opt, *assessed, report, opt.json ? &summary : nullptr);
  }
  if (opt.json) {
    std::cout << summary.dump(2) << "\n";
  } else {
    std::printf("replayed         %s: session %lld, scene %s, %lld steps at %g Hz\n",
                opt.replay.c_str(), static_cast<long long>(r.session_id), r.scene.c_str(),
                static_cast<long long>(r.steps), r.rate_hz);
    std::printf("reproduced       %lld recorded skeleton states, largest deviation %.3g m%s\n",
                static_cast<long long>(r.skeletons_compared), r.max_deviation,
                r.max_deviation == 0.0 ? " (exact)" : "");
    std::printf(
        "force messages   %lld compared, %lld differ%s%s\n",
        static_cast<long long>(r.forces_compared), static_cast<long long>(r.force_mismatches),
        r.force_mismatches == 0 ? " (exact)" : ": first at ", r.first_force_mismatch.c_str());
  }
  return 0;
}

int Run(const Options& opt) {
  scene::Scene scene = scene::LoadSceneFile(opt.scene);
  if (opt.rate_hz != 0.0) {
    ThrowUnless(std::isfinite(opt.rate_hz) && opt.rate_hz > 0.0, "--rate ", opt.rate_hz,
                ": must be > 0");
    scene::ChangeRate(&scene.model, opt.rate_hz);
  }
  for (const std::string& w : scene.warnings)
    std::cerr << "warning: " << opt.scene << ": " << w << std::endl;
  const mechanics::Model model = [&] {
    try {
      return mechanics::Model(scene.model);
    } catch (const InputError& e) {
      Fail(opt.scene, ": ", e.what());
    }
  }();
  for (const std::string& w : model.warnings())
    std::cerr << "warning: " << opt.scene << ": " << w << std::endl;
  ThrowUnless(opt.duration > 0.0 && std::isfinite(opt.duration), "--duration ", opt.duration,
              ": must be > 0");
  ThrowUnless(opt.trace_every >= 1, "--trace-every ", opt.trace_every, ": must be >= 1");

  ScriptedRun run(model, opt.tool_script);
  const State& state = run.state();
  mechanics::Interactions* interactions = run.interactions();
  if (model.params().integrator == mechanics::IntegratorKind::kRk4) {
    const mechanics::StabilityEstimate est = mechanics::EstimateStability(model, state);
    if (!est.stable()) {
      std::cerr << "warning: RK4 step beyond its stability limit: h * omega_max = "
                << est.h_times_rate << " > " << mechanics::kRk4StabilityLimit
                << " (h = " << model.substep_size() << " s, omega_max = " << est.rate_max
                << " 1/s); set [simulation] substeps >= " << est.stable_substeps
                << " or integrator = \"implicit\"\n";
    }
  }

  std::unique_ptr<TraceWriter> trace;
  if (!opt.trace.empty()) trace = std::make_unique<TraceWriter>(opt.trace);
  const spline::CatmullRom& curve = model.curve();
  auto energies = [&] {
    return mechanics::ComputeEnergies(model, state.q, state.qd, interactions);
  };
  auto record = [&](double step_us) {
    if (trace) trace->Write(model, state, interactions, curve.Length(state.q), energies(), step_us);
  };
  render::Laparoscope scope = RunScope(opt, model.params(), state.q);
  std::optional<script::CameraScript> camera_script;
  if (!opt.camera_script.empty()) {
    ThrowUnless(opt.camera.empty(), "--camera and --camera-script: give one");
    camera_script = script::CameraScript::Load(opt.camera_script);
  }
  // The scene's scope (its light and field of view) where the camera script puts it at t, on
  // the tool script's clock (it stands while a tool reaches again for a grasp).
  auto move_camera = [&](double t) {
    const script::CameraKeyframe k = camera_script->At(t - run.script_delay());
    scope.eye = k.eye.cast<float>();
    scope.target = k.target.cast<float>();
  };
  if (camera_script) move_camera(state.t);
  SimAssessment assessed(model, ViewOf(scope, opt));

  const Energies e0 = energies();
  const Vec3 com0 = model.CentreOfMass(state.q);
  const Vec3 momentum0 = Momentum(model, state);
  Vec3 hand_impulse = Vec3::Zero();  // what the hands gave the tips, all tools (N s)
  record(0.0);
  assessed.AddStep(state);
  const int64_t steps = run.StepsFor(opt.duration);
  std::unique_ptr<FrameWriter> frames;
  const int render_every =
      opt.render_every > 0
          ? opt.render_every
          : std::max(1, static_cast<int>(std::lround(model.params().rate_hz / 25.0)));
  if (!opt.render_dir.empty()) {
    ThrowUnless(opt.render_every >= 0, "--render-every ", opt.render_every,
                ": must be >= 1 (0: about 25 per second)");
    frames = std::make_unique<FrameWriter>(opt, model, scope);
    frames->Write(state);
  }
  std::vector<double> cost_us;
  cost_us.reserve(static_cast<size_t>(steps));
  ProgressBar progress(steps);
  double min_clearance = std::numeric_limits<double>::infinity();
  std::vector<double> max_tool_force(model.params().tools.size(), 0.0);
  for (int64_t k = 1; k <= steps; ++k) {
    const std::span<const mechanics::ToolTarget> targets = run.NextTargets();
    const int64_t begin = ThreadCpuNanos();
    run.Step(targets);
    const double us = (ThreadCpuNanos() - begin) * 1e-3;
    cost_us.push_back(us);
    if (camera_script) {
      move_camera(state.t);
      assessed.SetView(ViewOf(scope, opt));
      if (frames) frames->SetScope(scope);
    }
    if (!std::isnan(state.contacts.min_clearance))
      min_clearance = std::min(min_clearance, state.contacts.min_clearance);
    for (size_t t = 0; t < state.tools.size(); ++t) {
      max_tool_force[t] = std::max(max_tool_force[t], state.tools[t].force.norm());
      hand_impulse -= model.step_size() * state.tools[t].force;  // the hand feels the reaction
    }
    assessed.AddStep(state);
    if (k % opt.trace_every == 0 || k == steps) record(us);
    if (frames && k % render_every == 0) frames->Write(state, assessed.DamagedRanges());
    progress.Update(k);
  }

  const Energies e = energies();
  if (!opt.export_mesh.empty()) ExportMesh(opt, model, state.q);
  const Vec3 com = model.CentreOfMass(state.q);
  double total_us = 0.0;
  for (double c : cost_us) total_us += c;
  const double simulated = state.t;
  nlohmann::json summary = {
      {"scene", opt.scene},
      {"control_points", model.num_points()},
      {"integrator",
       model.params().integrator == mechanics::IntegratorKind::kRk4 ? "rk4" : "implicit"},
      {"rate_hz", model.params().rate_hz},
      {"substeps", model.params().substeps},
      {"frames", trace ? trace->frames() : 0},
      {"steps", steps},
      {"simulated_seconds", simulated},
      {"step_cost_us",
       {{"mean", total_us / steps},
        {"p99", Quantile(cost_us, 0.99)},
        {"max", *std::max_element(cost_us.begin(), cost_us.end())}}},
      {"realtime_factor", simulated / (total_us * 1e-6)},
      {"initial_energy", e0.total()},
      {"final_energy",
       {{"kinetic", e.kinetic},
        {"gravity", e.gravity},
        {"stretch", e.stretch},
        {"bend", e.bend},
        {"continuous", e.continuous},
        {"attachment", e.attachment},
        {"total", e.total()}}},
      {"rest_length", model.params().length},
      {"final_length", curve.Length(state.q)},
      {"centre_of_mass_start", {com0.x(), com0.y(), com0.z()}},
      {"centre_of_mass_end", {com.x(), com.y(), com.z()}},
      {"nonfinite_resets", state.nonfinite_resets},
      {"contacts",
       {{"self", state.contacts.self},
        {"environment", state.contacts.environment},
        {"tool", state.contacts.tool}}},
      {"min_clearance",
       std::isfinite(min_clearance) ? nlohmann::json(min_clearance) : nlohmann::json(nullptr)},
      {"sphere_radius", interactions ? interactions->chain().radius() : 0.0},
      {"max_tool_force", max_tool_force},  // per tool, in scene order (N)
      // the tube's and the tips' momentum gained, and the impulse the hands gave (N s): equal
      // for a free tube pushed by tool tips; gravity, walls, attachments and the ports (for a
      // shaft's contacts) give the rest
      {"momentum",
       {{"gained", Json(Momentum(model, state) - momentum0)}, {"hands", Json(hand_impulse)}}},
  };
  if (frames) summary["rendered_frames"] = frames->frames();
  // sub-steps the implicit step's linearization guard did again as halves (docs/integrators.md)
  const auto* implicit = dynamic_cast<const mechanics::ImplicitEulerIntegrator*>(&run.integrator());
  summary["halved_substeps"] = implicit ? implicit->halved_substeps() : 0;
  // the linear solve's stops (docs/integrators.md): solves that needed more than the usual
  // iterations, sub-steps halved because a solve did not converge, and solves accepted short
  summary["cg_extended"] = implicit ? implicit->cg_extended() : 0;
  summary["cg_halved"] = implicit ? implicit->cg_halved() : 0;
  summary["unconverged_solves"] = state.unconverged_solves;
  // sub-steps taken as BDF2, and those done again as backward Euler for their impacts
  summary["bdf2_substeps"] = implicit ? implicit->bdf2_substeps() : 0;
  summary["impact_redos"] = implicit ? implicit->impact_redos() : 0;
  summary["stretch_redos"] = implicit ? implicit->stretch_redos() : 0;
  summary["friction_redos"] = implicit ? implicit->friction_redos() : 0;
  summary["final_energy"]["contact"] = e.contact;
  // grasp rows the tool script reached again, and the time that took (docs/tool-coupling.md)
  summary["script_reaches"] = run.script_reaches();
  summary["script_delay"] = run.script_delay();
  assessment::Report report = assessed.Report(0, opt.scene);
  report.sim_time = simulated;
  if (opt.json) {
    EmitAssessment(opt, assessed, report, &summary);
    std::cout << summary.dump(2) << "\n";
    return 0;
  }
  std::printf("scene            %s (%d control points, %s, %g Hz x %d sub-steps)\n",
              opt.scene.c_str(), model.num_points(),
              summary["integrator"].get<std::string>().c_str(), model.params().rate_hz,
              model.params().substeps);
  std::printf("simulated        %.3f s in %lld steps, %d trace frames%s%s\n", simulated,
              static_cast<long long>(steps), trace ? trace->frames() : 0, trace ? " -> " : "",
              opt.trace.c_str());
  if (run.script_reaches() > 0)
    std::printf("tool script      %d grasps reached again, %.2f s behind its clock\n",
                run.script_reaches(), run.script_delay());
  std::printf("step cost        mean %.1f us, p99 %.1f us  (%.0fx real time on one core)\n",
              total_us / steps, Quantile(cost_us, 0.99), simulated / (total_us * 1e-6));
  std::printf("centre of mass   z %.4f m -> %.4f m", com0.z(), com.z());
  if (!interactions && model.pins().empty() && model.attachments().empty()) {
    // A free body: its centre of mass falls like a point with viscous friction gamma.
    const double gamma = model.params().damping, g = model.params().gravity.z(), t = simulated;
    const double expected =
        gamma > 0.0 ? g / gamma * (t - (1.0 - std::exp(-gamma * t)) / gamma) : 0.5 * g * t * t;
    std::printf(" (point under gravity and viscous friction: %.4f m)", com0.z() + expected);
  }
  std::printf("\n");
  std::printf("length           rest %.4f m, final %.4f m (%+.2f %%)\n", model.params().length,
              curve.Length(state.q), 100.0 * (curve.Length(state.q) / model.params().length - 1.0));
  std::printf(
      "energy           %.4f J -> %.4f J (kinetic %.4f, gravity %.4f, stretch %.4f, bend %.4f, "
      "continuous %.4f)\n",
      e0.total(), e.total(), e.kinetic, e.gravity, e.stretch, e.bend, e.continuous);
  if (interactions) {
    std::printf(
        "contacts         self %d, environment %d, tool %d; deepest penetration over the run %.2f "
        "mm (%.0f %% of the radius)\n",
        state.contacts.self, state.contacts.environment, state.contacts.tool,
        std::isfinite(min_clearance) ? std::max(0.0, -min_clearance) * 1e3 : 0.0,
        std::isfinite(min_clearance)
            ? 100.0 * std::max(0.0, -min_clearance) / interactions->chain().radius()
            : 0.0);
  }
  for (size_t t = 0; t < state.tools.size(); ++t) {
    const Vec3& f = state.tools[t].force;
    std::printf("tool %-11s force [%.3f, %.3f, %.3f] N, max over the run %.3f N%s\n",
                model.params().tools[t].name.c_str(), f.x(), f.y(), f.z(), max_tool_force[t],
                state.tools[t].grasping ? ", grasping" : "");
  }
  if (!state.tools.empty()) {
    const Vec3 gained = Momentum(model, state) - momentum0;
    std::printf(
        "momentum         tube and tips gained [%.5f, %.5f, %.5f] N s; hands gave [%.5f, %.5f, "
        "%.5f] N s\n",
        gained.x(), gained.y(), gained.z(), hand_impulse.x(), hand_impulse.y(), hand_impulse.z());
  }
  if (frames) {
    std::printf("frames           %d (%s skin, %s, every %d steps, %.1f ms each) -> %s\n",
                frames->frames(), opt.skin.c_str(), opt.frame_size.c_str(), render_every,
                frames->mean_ms(), opt.render_dir.c_str());
  }
  EmitAssessment(opt, assessed, report, nullptr);
  if (state.nonfinite_resets > 0) {
    std::printf("WARNING          %lld non-finite steps were reset\n",
                static_cast<long long>(state.nonfinite_resets));
  }
  return 0;
}

}  // namespace
}  // namespace viscera::tools

int main(int argc, char** argv) {
  viscera::tools::Options opt;
  CLI::App app{"viscera-sim: run a viscera scene offline and report what happened"};
  app.add_option("scene", opt.scene, "scene file (TOML); not with --replay");
  app.add_option("--replay", opt.replay,
                 "replay a viscerad session record (LCM log) instead of a scene");
  app.add_option("--duration", opt.duration, "simulated seconds")->capture_default_str();
  app.add_option("--rate", opt.rate_hz,
                 "mechanics rate (Hz) instead of the scene's; sub-steps keep the scene's length");
  app.add_option("--trace", opt.trace, "write a JSON Lines trace to this file");
  app.add_option("--trace-every", opt.trace_every, "record every N-th step")->capture_default_str();
  app.add_flag("--json", opt.json, "print the final summary as JSON");
  app.add_option("--tool-script", opt.tool_script,
                 "CSV of tool targets: t,tool,x,y,z,qw,qx,qy,qz,jaw");
  app.add_option("--skin", opt.skin,
                 "skin for --export-mesh and --render: parametric, implicit, convolution or hybrid")
      ->capture_default_str();
  app.add_option("--export-mesh", opt.export_mesh,
                 "write the last frame's skin mesh (.obj or .ply)");
  app.add_option("--focus", opt.focus, "hybrid skin focus centre x y z (m)")->expected(3);
  app.add_option("--focus-radius", opt.focus_radius, "hybrid skin focus radius (m)")
      ->capture_default_str();
  app.add_option("--render", opt.render_dir, "write JPEG frames of the run to this directory");
  app.add_option("--render-every", opt.render_every,
                 "steps between frames (default: about 25 per simulated second)");
  app.add_option("--camera", opt.camera, "laparoscope eye x y z and look-at x y z (m)")
      ->expected(6);
  app.add_option("--camera-script", opt.camera_script,
                 "CSV moving the laparoscope: t,ex,ey,ez,cx,cy,cz (s, eye and look-at in m)");
  app.add_option("--frame-size", opt.frame_size, "frame size WIDTHxHEIGHT")->capture_default_str();
  app.add_option("--report", opt.report,
                 "write the assessment (docs/assessment.md) as JSON to this file");
  app.add_option("--jpeg-quality", opt.jpeg_quality, "JPEG quality 1..100")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    if (!opt.replay.empty()) return viscera::tools::Replay(opt);
    viscera::ThrowUnless(!opt.scene.empty(), "a scene file (or --replay RECORD) is required");
    return viscera::tools::Run(opt);
  } catch (const viscera::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  }
}
