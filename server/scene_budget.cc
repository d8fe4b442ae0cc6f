#include "server/scene_budget.h"

#include <sys/stat.h>

#include <algorithm>
#include <cstdlib>
#include <memory>

#include "common/check.h"
#include "common/clock.h"
#include "mechanics/model.h"
#include "mechanics/step.h"

namespace viscera::server {
namespace {

constexpr size_t kMaxFileName = 255;
constexpr int kMaxProbeSteps = 50;

std::string RealPath(const std::string& path) {
  char* resolved = realpath(path.c_str(), nullptr);
  if (resolved == nullptr) return "";
  std::string out(resolved);
  std::free(resolved);
  return out;
}

// `text` with control bytes shown as '?', at most 80 characters: it goes into a reply.
std::string Printable(const std::string& text) {
  std::string out = text.substr(0, 80);
  for (char& c : out) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  }
  return text.size() > 80 ? out + "..." : out;
}

}  // namespace

std::string ResolveSceneFile(const std::string& scene_dir, const std::string& file,
                             int64_t max_bytes) {
  const auto refuse = [&](const std::string& why) {
    Fail("file \"", Printable(file), "\": ", why);
  };
  if (file.empty()) refuse("empty");
  if (file.size() > kMaxFileName) refuse(Cat("longer than ", kMaxFileName, " characters"));
  if (file.find('\0') != std::string::npos) refuse("contains a NUL byte");
  if (file[0] == '/')
    refuse("absolute paths are refused; name a file in the server's scene directory");
  for (size_t start = 0; start <= file.size();) {
    const size_t end = std::min(file.find('/', start), file.size());
    if (file.compare(start, end - start, "..") == 0)
      refuse("\"..\" is refused; name a file in the server's scene directory");
    start = end + 1;
  }
  const std::string dir = RealPath(scene_dir);
  ThrowUnless(!dir.empty(), "the server's scene directory '", scene_dir, "' is missing");
  const std::string path = RealPath(dir + "/" + file);
  if (path.empty()) refuse("no such file in the server's scene directory");
  if (path.compare(0, dir.size() + 1, dir + "/") != 0)
    refuse("leads outside the server's scene directory");
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) refuse("cannot be examined");
  if (!S_ISREG(st.st_mode))
    refuse("not a regular file (devices, FIFOs, sockets and directories are refused)");
  if (st.st_size > max_bytes)
    refuse(Cat(st.st_size, " bytes: above this server's limit of ", max_bytes));
  return path;
}

double EstimateMechanicsLoad(const mechanics::ModelParams& params, double rate_hz,
                             double budget_s) {
  const mechanics::Model model(params);
  mechanics::State state = mechanics::InitialState(model);
  mechanics::Workspace workspace(model);
  mechanics::Step(model, {}, &state, &workspace);  // the first step warms caches and allocates
  const int64_t start = ThreadCpuNanos();
  const int64_t budget_ns = static_cast<int64_t>(budget_s * 1e9);
  int steps = 0;
  while (steps < kMaxProbeSteps && ThreadCpuNanos() - start < budget_ns) {
    mechanics::Step(model, {}, &state, &workspace);
    ++steps;
  }
  const double per_step_s =
      static_cast<double>(ThreadCpuNanos() - start) * 1e-9 / std::max(steps, 1);
  return per_step_s * (rate_hz > 0.0 ? rate_hz : params.rate_hz);
}

std::function<void()> BuildStopCheck(std::shared_ptr<const std::atomic<bool>> stop, double max_s) {
  const int64_t deadline_ns = MonotonicNanos() + static_cast<int64_t>(max_s * 1e9);
  return [stop = std::move(stop), deadline_ns, max_s] {
    ThrowUnless(!stop->load(), "the server is stopping: the scene's build was abandoned");
    ThrowUnless(max_s <= 0.0 || MonotonicNanos() < deadline_ns,
                "the scene's build took longer than this server's ", "limit of ", max_s,
                " s (a shorter settle, fewer control points or sub-steps)");
  };
}

scene::SceneLimits NetworkSceneLimits(const ServerConfig& config, double session_rate_hz) {
  scene::SceneLimits limits;
  limits.max_control_points = config.max_control_points;
  limits.max_obstacles = config.max_obstacles;
  limits.max_mesh_resolution = config.max_mesh_resolution;
  limits.max_substeps = config.max_substeps;
  limits.max_rate_hz = config.max_rate_hz;
  limits.max_settle_s = config.max_settle_s;
  limits.max_spheres = config.max_spheres;
  limits.max_margin_radii = config.max_margin_radii;
  limits.max_tools = config.max_tools;
  limits.max_mesh_triangles = config.max_mesh_triangles;
  const std::string scene_dir = config.scene_dir;
  const int64_t max_bytes = config.max_mesh_bytes;
  limits.resolve_file = [scene_dir, max_bytes](const std::string& file) {
    return ResolveSceneFile(scene_dir, file, max_bytes);
  };
  const double max_load = config.max_session_load;
  limits.vet = [max_load, session_rate_hz](const mechanics::ModelParams& params, bool settled) {
    if (max_load <= 0.0) return;
    // Timed as it will run. A scene that settles is timed on its settled pile, which is what
    // the session runs, at the session's rate (its sub-steps adjusted), or the scene's. Before
    // the settle is paid for, its start (a falling coil, tethers pulling in, several times a
    // settled step), as the settle runs it (SceneLimits::vet: at the scene's own rate, whatever
    // the session's), must already fit kUnsettledLoadFactor times the limit.
    const double limit = settled ? max_load : kUnsettledLoadFactor * max_load;
    mechanics::ModelParams as_run = params;
    if (settled && session_rate_hz > 0.0) scene::ChangeRate(&as_run, session_rate_hz);
    const double rate = as_run.rate_hz;
    const double load = EstimateMechanicsLoad(as_run, rate);
    ThrowUnless(load <= limit, "estimated mechanics load ", load, " of a core at ", rate, " Hz",
                settled ? "" : " while settling", ": above this server's limit of ", limit,
                " (fewer control points, obstacles or substeps, or a lower rate)");
  };
  return limits;
}

}  // namespace viscera::server
