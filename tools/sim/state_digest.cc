// viscera-state-digest: runs a scene as viscera-sim does (same start, same tool script, same
// steps) and prints a 64-bit FNV-1a digest of every bit of the state after each step (t, q, qd,
// the tools' poses and forces, the contact counts and deepest clearance), cumulative, every
// --every steps and at the end. Two builds whose digests agree produced bit-identical runs: the
// check behind performance work that must not move the rounding (docs/benchmarks.md).
//   viscera-state-digest SCENE.toml --duration S [--rate HZ] [--tool-script CSV] [--every N]
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

#include "mechanics/step.h"
#include "scene/scene.h"
#include "script/scripted_tools.h"

namespace {

using namespace viscera;

class Digest {
 public:
  void Bytes(const void* data, size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) {
      hash_ ^= p[i];
      hash_ *= 0x100000001b3ULL;
    }
  }
  template <typename T>
  void Value(const T& v) {
    Bytes(&v, sizeof v);
  }
  void Matrix(const Points& m) { Bytes(m.data(), sizeof(double) * static_cast<size_t>(m.size())); }
  uint64_t value() const { return hash_; }

 private:
  uint64_t hash_ = 0xcbf29ce484222325ULL;
};

void AddState(const mechanics::State& s, Digest* d) {
  d->Value(s.t);
  d->Matrix(s.q);
  d->Matrix(s.qd);
  for (const mechanics::ToolState& tool : s.tools) {
    for (const Vec3* v : {&tool.tip, &tool.tip_velocity, &tool.force, &tool.torque, &tool.tissue_force}) {
      d->Bytes(v->data(), 3 * sizeof(double));
    }
    d->Value(tool.grasping);
    d->Value(tool.grasp_s);
    d->Value(tool.coupling_scale);
  }
  d->Value(s.contacts.self);
  d->Value(s.contacts.environment);
  d->Value(s.contacts.tool);
  d->Value(s.contacts.min_clearance);
  d->Value(s.substeps);
  d->Value(s.nonfinite_resets);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Digest of every step's state: bit-identical runs print the same digests"};
  std::string scene_path, tool_script;
  double duration = 1.0, rate_hz = 0.0;
  int every = 100;
  app.add_option("scene", scene_path, "scene TOML")->required();
  app.add_option("--duration", duration, "simulated seconds")->required();
  app.add_option("--rate", rate_hz, "step rate (Hz), the scene's sub-step length kept");
  app.add_option("--tool-script", tool_script, "tool script CSV");
  app.add_option("--every", every, "print the running digest every N steps")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  scene::Scene scene = scene::LoadSceneFile(scene_path);
  if (rate_hz != 0.0) scene::ChangeRate(&scene.model, rate_hz);
  const mechanics::Model model(scene.model);
  mechanics::State state = mechanics::InitialState(model);
  mechanics::Workspace workspace(model);
  mechanics::Interactions* interactions = workspace.interactions();
  std::optional<script::ScriptedTools> scripted;
  if (!tool_script.empty()) scripted.emplace(model, script::ToolScript::Load(tool_script), tool_script);
  auto targets_at = [&](double t) {
    return scripted ? scripted->At(t, interactions) : std::span<const mechanics::ToolTarget>{};
  };
  // As viscera-sim: the sphere chain of the start, before the first step.
  if (interactions) interactions->BeginSubstep(targets_at(0.0), 0.0, &state);
  const int64_t steps = std::max<int64_t>(1, std::llround(duration * model.params().rate_hz));
  Digest digest;
  for (int64_t k = 1; k <= steps; ++k) {
    mechanics::Step(model, {{}, targets_at(state.t + model.step_size())}, &state, &workspace);
    AddState(state, &digest);
    if (k % every == 0 || k == steps) {
      std::printf("step %lld t %.6f digest %016llx\n", static_cast<long long>(k), state.t,
                  static_cast<unsigned long long>(digest.value()));
    }
  }
  return 0;
}
