#pragma once
/// HeartbeatSource: builds the server's heartbeat_t messages, measuring its load.
#include <cstdint>
#include <string>

#include <viscera_proto/heartbeat_t.hpp>

#include "server/server_config.h"

namespace viscera::server {

/// CPU time used by every thread of this process (ns).
int64_t ProcessCpuNanos();

/// Writes the limits of `config` into a heartbeat (clients and operators see what a server
/// will refuse before asking).
void PutLimits(const ServerConfig& config, viscera_proto::heartbeat_t* heartbeat);

class HeartbeatSource {
 public:
  /// @throws InputError when server_id is empty or max_sessions < 1.
  HeartbeatSource(std::string server_id, int max_sessions);

  /// The next heartbeat: sequence numbers count up from 0; load is the process's CPU
  /// time since the previous call (or since construction) over the wall time elapsed.
  /// @pre 0 <= num_sessions, 0 <= rejected (messages dropped since start).
  viscera_proto::heartbeat_t Next(int num_sessions, int64_t rejected = 0);

 private:
  std::string server_id_;
  int max_sessions_;
  int64_t seq_ = 0;
  int64_t start_wall_ns_;
  int64_t last_wall_ns_;
  int64_t last_cpu_ns_;
};

}  // namespace viscera::server
