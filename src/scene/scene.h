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

}  // namespace viscera::scene
