#pragma once
/// Scene files (TOML, SI units): the model, the environment and what the runner must say about
/// parts it does not simulate yet. The keys are documented in docs/scenes.md.
#include <string>
#include <vector>

#include "mechanics/model_params.h"

namespace viscera::scene {

struct Scene {
  std::string source;                ///< file path or "<string>"
  mechanics::ModelParams model;  ///< includes contacts, obstacles and tools
  /// Things the user should know: unknown top-level tables.
  std::vector<std::string> warnings;
};

/// @throws InputError with the file, the key, the value and the reason.
Scene LoadSceneFile(const std::string& path);

/// Same from TOML text; `source` names it in messages.
Scene ParseScene(const std::string& text, const std::string& source = "<string>");

/// Runs the scene at another rate while keeping what its `substeps` meant: a sub-step no longer
/// than the scene's own, 1 / (rate_hz * substeps) as written. A 100 Hz scene with 2 sub-steps
/// (5 ms) takes 1 sub-step at 1 kHz, not 2 of 0.5 ms.
/// @pre rate_hz > 0.
void ChangeRate(mechanics::ModelParams* params, double rate_hz);

}  // namespace viscera::scene
