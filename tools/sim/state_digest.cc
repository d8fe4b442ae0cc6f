// viscera-state-digest: runs a scene as viscera-sim does (same start, same tool script, same
// steps) and prints a 64-bit FNV-1a digest of every bit of the state after each step (t, q, qd,
// the tools' poses and forces, the contact counts and deepest clearance), cumulative, every
// --every steps and at the end. Two builds whose digests agree produced bit-identical runs: the
// check behind performance work that must not move the rounding (docs/performance.md).
//   viscera-state-digest SCENE.toml --duration S [--rate HZ] [--tool-script CSV] [--every N]
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "scene/scene.h"
#include "sim/scripted_run.h"

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
    for (const Vec3* v :
         {&tool.tip, &tool.tip_velocity, &tool.force, &tool.torque, &tool.tissue_force}) {
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
  app.add_option("--every", every, "print the running digest every N steps")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  scene::Scene scene = scene::LoadSceneFile(scene_path);
  if (rate_hz != 0.0) scene::ChangeRate(&scene.model, rate_hz);
  const mechanics::Model model(scene.model);
  tools::ScriptedRun run(model, tool_script);
  const mechanics::State& state = run.state();
  const int64_t steps = run.StepsFor(duration);
  Digest digest;
  for (int64_t k = 1; k <= steps; ++k) {
    run.Step(run.NextTargets());
    AddState(state, &digest);
    if (k % every == 0 || k == steps) {
      std::printf("step %lld t %.6f digest %016llx\n", static_cast<long long>(k), state.t,
                  static_cast<unsigned long long>(digest.value()));
    }
  }
  return 0;
}
