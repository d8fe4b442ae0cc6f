#include "render/jpeg_sequence.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "common/check.h"

namespace viscera::render {

JpegSequence::JpegSequence(std::string directory) : directory_(std::move(directory)) {
  std::error_code error;
  std::filesystem::create_directories(directory_, error);
  ThrowUnless(std::filesystem::is_directory(directory_), directory_,
              ": cannot create the frame directory", error ? ": " + error.message() : "");
}

std::string JpegSequence::Write(const std::vector<uint8_t>& jpeg) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06d.jpg", frames_);
  const std::string path = (std::filesystem::path(directory_) / name).string();
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(jpeg.data()), static_cast<std::streamsize>(jpeg.size()));
  ThrowUnless(out.good(), path, ": cannot write the frame");
  ++frames_;
  return path;
}

}  // namespace viscera::render
