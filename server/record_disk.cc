#include "server/record_disk.h"

#include <sys/statvfs.h>

#include "common/check.h"

namespace viscera::server {

int64_t FreeBytes(const std::string& dir) {
  struct statvfs fs {};
  if (statvfs(dir.c_str(), &fs) != 0) return -1;
  return static_cast<int64_t>(fs.f_bavail) * static_cast<int64_t>(fs.f_frsize);
}

std::string RecordDiskProblem(const ServerConfig& config) {
  if (config.log_dir.empty() || config.min_record_free_bytes <= 0) return "";
  const int64_t free = FreeBytes(config.log_dir);
  if (free < 0) return Cat("the record directory '", config.log_dir, "' cannot be examined");
  if (free >= config.min_record_free_bytes) return "";
  return Cat("the record directory's disk has ", free >> 20,
             " MiB free, below this server's minimum of ", config.min_record_free_bytes >> 20,
             " MiB: no new session until there is room (running sessions go on)");
}

}  // namespace viscera::server
