#pragma once
/// JpegSequence: numbered JPEG files in a directory (frame_000000.jpg, frame_000001.jpg, ...).
#include <cstdint>
#include <string>
#include <vector>

namespace viscera::render {

class JpegSequence {
 public:
  /// Creates `directory` (and its parents) when missing.
  /// @throws InputError when it cannot be created or is not a directory.
  explicit JpegSequence(std::string directory);

  /// Writes the next frame's bytes and returns its path.
  /// @throws InputError when the file cannot be written.
  std::string Write(const std::vector<uint8_t>& jpeg);

  int frames() const { return frames_; }

 private:
  std::string directory_;
  int frames_ = 0;
};

}  // namespace viscera::render
