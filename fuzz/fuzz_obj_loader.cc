// The OBJ loader behind mesh obstacles (collision::MeshSdf::FromObj), on any file content: a
// scene may name any regular file in the server's scene directory.
#include <cstdint>
#include <exception>

#include "collision/mesh_sdf.h"
#include "common/check.h"
#include "fuzz/memory_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static viscera::fuzz::MemoryFile file;
  const std::string path = file.Hold(data, size);
  try {
    // the coarsest grid: the parser is under test, not the distance field's cost
    const auto sdf = viscera::collision::MeshSdf::FromObj(path, 1.0, viscera::Vec3::Zero(), 8);
    viscera::Vec3 normal;
    (void)sdf.Distance(viscera::Vec3(0.1, 0.2, 0.3), &normal);
  } catch (const viscera::InputError&) {
    // refused with a reason: what bad input must get
  }
  return 0;
}
