#pragma once
/// Scenes from the network are hostile input: what a create's scene may name (files inside
/// the server's scene directory only) and cost (docs/security.md, "Scene budget").
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "mechanics/model_params.h"
#include "scene/scene.h"
#include "server/server_config.h"

namespace viscera::server {

/// The file a scene's mesh `file` value names, as an absolute path inside `scene_dir`.
/// Refused (InputError with the reason): an empty, absolute or over-long name, a name with a
/// ".." component or a NUL, a file that does not exist, lies outside the directory once
/// symbolic links are resolved, is not a regular file (devices, FIFOs, sockets, directories)
/// or holds more than `max_bytes`. It never opens the file: nothing blocks on a FIFO.
std::string ResolveSceneFile(const std::string& scene_dir, const std::string& file,
                             int64_t max_bytes);

/// Fraction of one core the model's mechanics would use at `rate_hz`: the thread CPU time of
/// a few steps from its starting state (at most about `budget_s` of CPU), times the rate.
double EstimateMechanicsLoad(const mechanics::ModelParams& params, double rate_hz,
                             double budget_s = 0.2);

/// Before a scene's settle, its start as the settle runs it must fit this many times the load
/// limit (the settled pile must fit the limit itself): what an unsettled step may cost over a
/// settled one.
inline constexpr double kUnsettledLoadFactor = 4.0;

/// The limits of `config` for a create's scene; `session_rate_hz` (0: the scene's) is the
/// rate the session will run at, for the load estimate.
scene::SceneLimits NetworkSceneLimits(const ServerConfig& config, double session_rate_hz);

/// A SceneLimits::check_stop for a build that starts now: throws InputError once `stop` is
/// set (the server stops: a SIGTERM abandons builds instead of waiting minutes for them) or
/// `max_s` seconds of wall time have passed (0: no deadline).
std::function<void()> BuildStopCheck(std::shared_ptr<const std::atomic<bool>> stop, double max_s);

}  // namespace viscera::server
