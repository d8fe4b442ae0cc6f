#pragma once
/// HeartbeatSource: builds the server's heartbeat_t messages, measuring its load.
#include <cstdint>
#include <functional>
#include <string>

#include <viscera_proto/heartbeat_t.hpp>

#include "common/clock.h"
#include "server/server_config.h"

namespace viscera::server {

/// CPU time used by every thread of this process (ns).
int64_t ProcessCpuNanos();

/// Writes the limits of `config` into a heartbeat (clients and operators see what a server
/// will refuse before asking).
void PutLimits(const ServerConfig& config, viscera_proto::heartbeat_t* heartbeat);

/// Where the load's two times come from (ns): the process's CPU time and monotonic wall
/// time. Tests inject their own, so the load they check is exact rather than timed.
struct HeartbeatClocks {
  std::function<int64_t()> cpu_ns = ProcessCpuNanos;
  std::function<int64_t()> wall_ns = MonotonicNanos;
};

class HeartbeatSource {
 public:
  /// @throws InputError when server_id is empty or max_sessions < 1.
  HeartbeatSource(std::string server_id, int max_sessions, HeartbeatClocks clocks = {});

  /// The next heartbeat: sequence numbers count up from 0; load is the process's CPU
  /// time since the previous call (or since construction) over the wall time elapsed.
  /// @pre 0 <= num_sessions, 0 <= rejected (messages dropped since start).
  viscera_proto::heartbeat_t Next(int num_sessions, int64_t rejected = 0);

  /// The max_sessions announced from the next heartbeat on. @pre max_sessions >= 1.
  void SetMaxSessions(int max_sessions);
  /// Why max_sessions is what it is (heartbeat_t.capacity), from the next heartbeat on.
  void SetCapacityNote(std::string note) { capacity_note_ = std::move(note); }

 private:
  std::string server_id_;
  int max_sessions_;
  std::string capacity_note_;
  HeartbeatClocks clocks_;
  int64_t seq_ = 0;
  int64_t start_wall_ns_;
  int64_t last_wall_ns_;
  int64_t last_cpu_ns_;
};

}  // namespace viscera::server
