// The scene loader (TOML) as the server runs it on a create's inline scene: the network's
// limits (scene budget, files confined to the scene directory), then the model built.
#include <cstdint>
#include <string>

#include "common/check.h"
#include "fuzz/fuzz_limits.h"
#include "session/session_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const viscera::scene::SceneLimits limits = viscera::fuzz::FuzzSceneLimits();
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    viscera::session::LoadSessionScene(std::string(VISCERA_SOURCE_DIR) + "/scenes", "", text, 0.0, 1000.0,
                                       std::string(VISCERA_SOURCE_DIR) + "/scenes/<inline>", limits);
  } catch (const viscera::InputError&) {
  }
  return 0;
}
