// The scene loader (TOML) as the server runs it on a create's inline scene: the network's
// limits (scene budget, files confined to the scene directory), then the model built.
#include <cstdint>
#include <string>

#include "common/check.h"
#include "server/scene_budget.h"
#include "session/session_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const viscera::scene::SceneLimits limits = [] {
    viscera::server::ServerConfig config;
    config.scene_dir = std::string(VISCERA_SOURCE_DIR) + "/scenes";
    // small budgets keep each input fast; the checks are the same as with the defaults
    config.max_control_points = 64;
    config.max_obstacles = 8;
    config.max_mesh_resolution = 12;
    config.max_substeps = 4;
    config.max_settle_s = 0.05;
    config.max_session_load = 0.0;  // no timing probe: it would only slow the fuzzer
    return viscera::server::NetworkSceneLimits(config, 0.0);
  }();
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    viscera::session::LoadSessionScene(std::string(VISCERA_SOURCE_DIR) + "/scenes", "", text, 0.0, 1000.0,
                                       std::string(VISCERA_SOURCE_DIR) + "/scenes/<inline>", limits);
  } catch (const viscera::InputError&) {
  }
  return 0;
}
