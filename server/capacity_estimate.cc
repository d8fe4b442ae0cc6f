#include "server/capacity_estimate.h"

#include <sched.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <thread>
#include <vector>

#include "common/check.h"
#include "common/clock.h"
#include "render/frame_renderer.h"
#include "render/port_scope.h"
#include "session/session_scene.h"
#include "session/stepper.h"

namespace viscera::server {
namespace {

constexpr int kWarmupSteps = 5;  // first steps fill caches and factor the solver
constexpr int kMinSteps = 20;
constexpr int kFrames = 5;  // after one warm-up frame (context, buffers, skin binding)

void StopIfAsked(const std::function<bool()>& stop) {
  if (stop && stop()) throw MeasurementStopped();
}

double Median(std::vector<double> v) {
  VISCERA_DEMAND(!v.empty());
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// CPU ms of one frame (skin, draw, JPEG) of `state`, on the calling thread.
double MeasureFrame(const mechanics::Model& model, const mechanics::State& state,
                    const ServerConfig& config, const std::function<bool()>& stop) {
  render::FrameOptions options;
  options.width = config.frame_width;
  options.height = config.frame_height;
  options.jpeg_quality = config.jpeg_quality;
  options.skin = config.skin;
  options.skin_options.parametric.sides = config.skin_sides;
  options.skin_options.convolution.sides = config.skin_sides;
  // every frame draws the intestine, as while a trainee handles it: the same state drawn again
  // would otherwise start from its kept picture and cost a fraction of that
  options.scene.keep_intestine = false;
  render::FrameRenderer renderer(model.params(), options);
  const render::Laparoscope camera =
      render::SceneLaparoscope(model.params(), state.q, renderer.width(), renderer.height());
  std::vector<double> costs;
  for (int i = 0; i <= kFrames; ++i) {
    StopIfAsked(stop);
    const int64_t cpu0 = ThreadCpuNanos();
    renderer.Render(state, camera);
    renderer.Encode();
    if (i > 0) costs.push_back(static_cast<double>(ThreadCpuNanos() - cpu0) * 1e-6);
  }
  return Median(costs);
}

}  // namespace

double CapacityEstimate::BudgetCores() const { return cores * kCoreBudget; }

double CapacityEstimate::FrameCores(double rate_hz, int width, int height) const {
  if (rate_hz <= 0.0 || frame_cpu_ms <= 0.0 || frame_width <= 0 || frame_height <= 0) return 0.0;
  const double pixels =
      static_cast<double>(width) * height / (static_cast<double>(frame_width) * frame_height);
  return frame_cpu_ms * 1e-3 * rate_hz * pixels;
}

double CapacityEstimate::SessionCores(double frame_rate_hz, int width, int height) const {
  return session_cores + FrameCores(frame_rate_hz, width, height);
}

std::string CapacityEstimate::Describe() const {
  const auto rounded = [](double x, double unit) { return std::lround(x / unit) * unit; };
  std::string frames = " (frames not measured)";
  if (frame_cpu_ms > 0.0) {
    const double stream = FrameCores(frame_rate_hz, frame_width, frame_height);
    frames = Cat(
        "; its ", frame_rate_hz, " Hz ", frame_width, "x", frame_height, " frame stream adds ",
        rounded(stream, 0.01), " core (a frame ", rounded(frame_cpu_ms, 0.1), " ms), so ",
        std::max(1, static_cast<int>(std::floor(BudgetCores() / (session_cores + stream) + 1e-9))),
        " with frames");
  }
  return Cat("max ", max_sessions, " sessions without frames: a ", scene, " session costs ",
             rounded(session_cores, 0.001), " core (a step ", std::lround(step_cpu_us), " us at ",
             rate_hz, " Hz)", frames, "; ", cores, " core(s) at ", std::lround(kCoreBudget * 100.0),
             " % = ", rounded(BudgetCores(), 0.01), " core");
}

int AvailableCores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1u, std::thread::hardware_concurrency());
}

int SessionsThatFit(int cores, double session_cores) {
  VISCERA_DEMAND(session_cores > 0.0 && cores >= 1);
  // 1e-9: a budget that holds exactly k sessions must not round to k - 1 (8 x 0.7 / 0.05)
  const double fit = std::floor(cores * kCoreBudget / session_cores + 1e-9);
  return static_cast<int>(std::clamp(fit, 1.0, 1024.0));
}

CapacityEstimate EstimateCapacity(const ServerConfig& config, const std::string& scene_name,
                                  double seconds, const std::function<bool()>& stop) {
  StopIfAsked(stop);
  const session::SessionScene scene = session::LoadSessionScene(config.scene_dir, scene_name, "",
                                                                config.rate_hz, config.max_rate_hz);
  StopIfAsked(stop);
  CapacityEstimate e;
  e.scene = scene.label;
  e.cores = AvailableCores();
  e.rate_hz = scene.model->params().rate_hz;

  // mechanics: the scene as a session starts it, no tool driven
  session::Stepper stepper(*scene.model);
  std::vector<double> costs;
  const int64_t end = MonotonicNanos() + static_cast<int64_t>(seconds * 1e9);
  for (int i = 0; i < kWarmupSteps + kMinSteps || MonotonicNanos() < end; ++i) {
    StopIfAsked(stop);
    const int64_t cpu0 = ThreadCpuNanos();
    stepper.Advance({});
    if (i >= kWarmupSteps) costs.push_back(static_cast<double>(ThreadCpuNanos() - cpu0) * 1e-3);
  }
  e.step_cpu_us = Median(costs);
  e.session_cores = e.step_cpu_us * 1e-6 * e.rate_hz;

  if (config.frame_rate_hz > 0.0) {
    e.frame_rate_hz = config.frame_rate_hz;
    std::exception_ptr error;
    std::thread render([&] {
      try {
        e.frame_cpu_ms = MeasureFrame(*scene.model, stepper.state(), config, stop);
      } catch (...) {
        error = std::current_exception();
      }
    });
    render.join();
    if (error) std::rethrow_exception(error);
    e.frame_width = config.frame_width;
    e.frame_height = config.frame_height;
  }
  e.max_sessions = SessionsThatFit(e.cores, e.session_cores);
  return e;
}

}  // namespace viscera::server
