#pragma once
// The scene limits the fuzz targets read scenes within: the server's checks, with small
// budgets so that each input stays fast (and no timing probe, which would only slow them).
#include <string>

#include "server/scene_budget.h"

namespace viscera::fuzz {

inline scene::SceneLimits FuzzSceneLimits() {
  server::ServerConfig config;
  config.scene_dir = std::string(VISCERA_SOURCE_DIR) + "/scenes";
  config.max_control_points = 64;
  config.max_obstacles = 8;
  config.max_mesh_resolution = 12;
  config.max_substeps = 4;
  config.max_settle_s = 0.05;
  config.max_session_load = 0.0;
  return server::NetworkSceneLimits(config, 0.0);
}

}  // namespace viscera::fuzz
