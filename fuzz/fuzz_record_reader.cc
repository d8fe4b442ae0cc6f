// The session record reader (session::ReplayRecord) on any file: a record may come from
// elsewhere, so its scene is read within a network-like budget.
#include <cstdint>
#include <string>

#include "common/check.h"
#include "fuzz/fuzz_limits.h"
#include "fuzz/memory_file.h"
#include "session/replay.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static viscera::fuzz::MemoryFile file;
  static const viscera::scene::SceneLimits limits = viscera::fuzz::FuzzSceneLimits();
  const std::string path = file.Hold(data, size);
  try {
    viscera::session::ReplayRecord(path, nullptr, limits);
  } catch (const viscera::InputError&) {
  }
  return 0;
}
