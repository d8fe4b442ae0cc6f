#pragma once
/// The model a session runs: a scene by name from the server's scene directory or inline
/// TOML, with the requested mechanics rate. Used by the server at create time and by replay.
#include <memory>
#include <string>
#include <vector>

#include "mechanics/model.h"
#include "scene/scene.h"

namespace viscera::session {

struct SessionScene {
  std::string label;  ///< scene name, or "<inline>"
  /// Absolute path of the scene file, or "<inline>": relative mesh paths resolve against it.
  std::string source;
  std::string toml;  ///< the scene text as loaded (kept in the session record)
  std::vector<std::string> warnings;
  std::shared_ptr<const mechanics::Model> model;
};

/// True for names made of [A-Za-z0-9_.-], 1..64 characters, not starting with '.': no
/// path can escape the scene directory.
bool ValidSceneName(const std::string& name);

/// Loads `scene_name` from `scene_dir` (NAME.toml) or, when scene_name is empty, parses
/// `scene_toml` as if it came from `inline_source` (a path: meshes it names relative resolve
/// against its directory), within `limits`; then sets the mechanics rate to `rate_hz` unless
/// it is 0.
/// @throws InputError when the name is invalid or unknown, both or neither source is
///         given, the scene is invalid, or rate_hz is not 0 and not in [1, max_rate_hz].
SessionScene LoadSessionScene(const std::string& scene_dir, const std::string& scene_name,
                              const std::string& scene_toml, double rate_hz, double max_rate_hz,
                              const std::string& inline_source = "<inline>",
                              const scene::SceneLimits& limits = scene::SceneLimits{});

}  // namespace viscera::session
