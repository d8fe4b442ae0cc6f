#pragma once
// The benchmarks' scenes: scenes/fall.toml resampled to any number of control points, and any
// scene file at another rate.
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "common/check.h"
#include "mechanics/model_params.h"
#include "scene/scene.h"

namespace viscera::bench {

inline constexpr const char* kFallScene = VISCERA_SOURCE_DIR "/scenes/fall.toml";

/// The fall scene with `n` control points (the same 4 m coil, its plane and its contacts).
inline mechanics::ModelParams FallParams(int n) {
  std::ifstream file(kFallScene);
  ThrowUnless(file.good(), kFallScene, ": cannot open");
  std::stringstream text;
  text << file.rdbuf();
  const std::regex key(R"(control_points\s*=\s*[0-9]+)");
  ThrowUnless(std::regex_search(text.str(), key), kFallScene, ": no intestine.control_points");
  const std::string resized =
      std::regex_replace(text.str(), key, "control_points = " + std::to_string(n),
                         std::regex_constants::format_first_only);
  mechanics::ModelParams params =
      scene::ParseScene(resized, "fall.toml, " + std::to_string(n) + " points").model;
  VISCERA_DEMAND(params.initial_q.rows() == n);
  return params;
}

/// The scene file at `path`, run at `rate_hz` (its sub-step length kept: scene::ChangeRate).
inline mechanics::ModelParams SceneAtRate(const char* path, double rate_hz) {
  mechanics::ModelParams params = scene::LoadSceneFile(path).model;
  scene::ChangeRate(&params, rate_hz);
  return params;
}

}  // namespace viscera::bench
