#pragma once
/// ServerDirectory: the servers heard on the heartbeat channel, latest heartbeat each.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <viscera_proto/heartbeat_t.hpp>

#include "bus/placement.h"

namespace viscera::client {

/// What the latest heartbeat of one server said: its room (server_id, sessions,
/// max_sessions, load as a fraction of one core) and more.
struct ServerInfo : bus::ServerLoad {
  double uptime_s = 0.0;           ///< s
  int64_t heartbeats = 0;          ///< heard while listening
  int64_t rejected = 0;            ///< messages the server dropped since it started
  int64_t record_free_bytes = -1;  ///< on the server's record disk (-1: it records nothing)
  int64_t not_ours = 0;            ///< messages for sessions it does not run (not rejected)
  int64_t unconverged_solves = 0;  ///< solves accepted short of tolerance, all its sessions
  int cores = 0;                   ///< CPUs the server may run on (0: not announced)
  std::string capacity;            ///< why it holds max_sessions ("" : not announced)
};

class ServerDirectory {
 public:
  /// Records a heartbeat. Heartbeats of another protocol version or with a broken
  /// header are not trusted: counted in rejected(), otherwise ignored.
  void Observe(const viscera_proto::heartbeat_t& heartbeat);

  /// Servers heard, sorted by id.
  std::vector<ServerInfo> Servers() const;
  int64_t rejected() const { return rejected_; }
  /// Why the last heartbeat was rejected ("" if none was).
  const std::string& last_rejection() const { return last_rejection_; }

 private:
  std::map<std::string, ServerInfo> servers_;
  int64_t rejected_ = 0;
  std::string last_rejection_;
};

/// The server a new session should go to (bus::PickServer: the least loaded with room),
/// or nullptr when every one is full or none was heard.
const ServerInfo* PickServer(const std::vector<ServerInfo>& servers);

/// "a 1/4, b 0/2" (id and sessions of each), for messages.
std::string ServersSummary(const std::vector<ServerInfo>& servers);

/// A JSON array of objects (keys in this order): server_id, sessions, max_sessions, load,
/// uptime_s, heartbeats, rejected, record_free_bytes, not_ours, unconverged_solves, cores,
/// capacity.
nlohmann::ordered_json ServersToJson(const std::vector<ServerInfo>& servers);

/// A table with a header line, one line per server, columns aligned, then per server the
/// line saying why it holds what it holds.
std::string ServersToTable(const std::vector<ServerInfo>& servers);

}  // namespace viscera::client
