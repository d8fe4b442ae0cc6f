// The session record reader (session::ReplayRecord) on any file: a record may come from
// elsewhere, so its scene is read within a network-like budget.
#include <cstdint>
#include <string>

#include "common/check.h"
#include "fuzz/memory_file.h"
#include "server/scene_budget.h"
#include "session/replay.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static viscera::fuzz::MemoryFile file;
  static const viscera::scene::SceneLimits limits = [] {
    viscera::server::ServerConfig config;
    config.scene_dir = std::string(VISCERA_SOURCE_DIR) + "/scenes";
    config.max_control_points = 64;
    config.max_obstacles = 8;
    config.max_mesh_resolution = 12;
    config.max_substeps = 4;
    config.max_settle_s = 0.05;
    config.max_session_load = 0.0;
    return viscera::server::NetworkSceneLimits(config, 0.0);
  }();
  const std::string path = file.Hold(data, size);
  try {
    viscera::session::ReplayRecord(path, nullptr, limits);
  } catch (const viscera::InputError&) {
  }
  return 0;
}
