#pragma once
// A file in memory (memfd) holding the fuzzer's input, for loaders that read a path.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <string>

namespace viscera::fuzz {

class MemoryFile {
 public:
  MemoryFile() : fd_(memfd_create("viscera-fuzz", 0)) {
    if (fd_ < 0) std::abort();
  }
  ~MemoryFile() { close(fd_); }
  /// Replaces the content with `data` and returns a path that opens it.
  std::string Hold(const uint8_t* data, size_t size) {
    if (ftruncate(fd_, 0) != 0 || pwrite(fd_, data, size, 0) != static_cast<ssize_t>(size))
      std::abort();
    return "/proc/self/fd/" + std::to_string(fd_);
  }

 private:
  int fd_;
};

}  // namespace viscera::fuzz
