#pragma once
/// Scene files (TOML, SI units): the model, the environment and what the runner must say about
/// parts it does not simulate yet. The keys are documented in docs/scenes.md.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "mechanics/model_params.h"

namespace viscera::scene {

struct Scene {
  std::string source;            ///< file path or "<string>"
  mechanics::ModelParams model;  ///< includes contacts, obstacles and tools
  /// Things the user should know: unknown top-level tables.
  std::vector<std::string> warnings;
};

/// What a scene from an untrusted source (a create over the network) may cost and name,
/// checked while reading, before anything expensive is built. 0 (or an empty function)
/// means no limit: the defaults trust the scene, as for local files.
struct SceneLimits {
  int max_control_points = 0;
  int max_obstacles = 0;
  int max_mesh_resolution = 0;  ///< grid cells along a mesh's longest side
  int max_substeps = 0;
  double max_rate_hz = 0.0;  ///< the scene's own [simulation] rate_hz (settling runs at it)
  double max_settle_s = 0.0;
  /// Collision spheres (one per radius of length, collision/sphere_chain.h): bounded from
  /// intestine.length / intestine.radius before the chain or anything else is allocated.
  int max_spheres = 0;
  /// contacts.margin in tube radii: a sphere's candidate pairs grow with the cube of its reach
  /// (2 radius + margin); a margin of a metre makes every pair a candidate.
  double max_margin_radii = 0.0;
  int max_tools = 0;           ///< [[tool]] tables: one force message per tool per step
  int max_mesh_triangles = 0;  ///< of a mesh obstacle, counted before its field is built
  /// Turns a mesh obstacle's `file` value into the path to open, or throws InputError (the
  /// server confines files to its scene directory). Empty: relative to the scene's directory.
  std::function<std::string(const std::string& file)> resolve_file;
  /// Called with the whole model once read, before settling (settled = false; only when the
  /// scene settles), as the settle's first steps run it (its friction, its mesentery's slack,
  /// the scene's rate), and with the settled model, which is what runs (settled = true): may
  /// throw InputError (the server estimates the step cost here).
  std::function<void(const mechanics::ModelParams&, bool settled)> vet;
  /// Called between the build's phases and before every settling step: throws InputError to
  /// abandon the build (the server's build deadline, or its shutdown).
  std::function<void()> check_stop;
};

/// @throws InputError with the file, the key, the value and the reason.
Scene LoadSceneFile(const std::string& path);

/// Same from TOML text; `source` names it in messages.
Scene ParseScene(const std::string& text, const std::string& source = "<string>");

/// Same, within `limits` (a limit exceeded is an InputError naming the key and the limit).
Scene ParseScene(const std::string& text, const std::string& source, const SceneLimits& limits);

/// Runs the scene at another rate while keeping what its `substeps` meant: a sub-step no longer
/// than the scene's own, 1 / (rate_hz * substeps) as written. A 100 Hz scene with 2 sub-steps
/// (5 ms) takes 1 sub-step at 1 kHz, not 2 of 0.5 ms.
/// @pre rate_hz > 0.
void ChangeRate(mechanics::ModelParams* params, double rate_hz);

}  // namespace viscera::scene
