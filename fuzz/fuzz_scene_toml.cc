// The scene loader (TOML) as the server runs it on a create's inline scene: the network's
// limits (scene budget, files confined to the scene directory), then the model built.
//
// An input that starts with byte 0x01 is a generator, so that a short input reaches the deep
// and long texts a hostile create sends (a key 40,000 levels deep is 80 KB): 0x01, a repeat
// count (two bytes, little-endian), then PREFIX \0 PART \0 SUFFIX; the scene is PREFIX, PART
// repeated, SUFFIX. Any other input is the scene itself (ctest runs with -max_len=131072 and
// fuzz/scene_toml.dict).
#include <cstdint>
#include <string>

#include "common/check.h"
#include "fuzz/fuzz_limits.h"
#include "session/session_scene.h"

namespace {

std::string Generate(const std::string& in) {
  if (in.size() < 3 || in[0] != '\x01') return in;
  const size_t count =
      static_cast<uint8_t>(in[1]) | (static_cast<size_t>(static_cast<uint8_t>(in[2])) << 8);
  const std::string rest = in.substr(3);
  const size_t a = rest.find('\0');
  const size_t b = a == std::string::npos ? std::string::npos : rest.find('\0', a + 1);
  if (b == std::string::npos) return in;
  const std::string part = rest.substr(a + 1, b - a - 1);
  std::string text = rest.substr(0, a);
  text.reserve(text.size() + part.size() * count + rest.size() - b);
  for (size_t i = 0; i < count && text.size() < (4u << 20); ++i) text += part;
  return text + rest.substr(b + 1);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const viscera::scene::SceneLimits limits = viscera::fuzz::FuzzSceneLimits();
  const std::string text = Generate(std::string(reinterpret_cast<const char*>(data), size));
  try {
    viscera::session::LoadSessionScene(std::string(VISCERA_SOURCE_DIR) + "/scenes", "", text, 0.0,
                                       1000.0, std::string(VISCERA_SOURCE_DIR) + "/scenes/<inline>",
                                       limits);
  } catch (const viscera::InputError&) {
  }
  return 0;
}
