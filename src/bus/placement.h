#pragma once
/// Where a new session should go: the one rule every viscera client and server uses to
/// rank servers from their heartbeats (the Python client's pick_server mirrors it).
#include <algorithm>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace viscera::bus {

/// What a heartbeat says about a server's room.
struct ServerLoad {
  std::string server_id;
  int sessions = 0;
  int max_sessions = 0;
  double load = 0.0;  ///< CPU time over wall time (fraction of one core)
};

/// True when `a` should take a new session before `b`: the lower share of its capacity in
/// use first (a big machine half full and a small one half full weigh alike), then the
/// lower CPU load, then the smaller id (so every client breaks ties alike).
/// @pre a.max_sessions > 0 and b.max_sessions > 0.
inline bool PlaceBefore(const ServerLoad& a, const ServerLoad& b) {
  // a.sessions / a.max_sessions < b.sessions / b.max_sessions, exactly
  const long long lhs = static_cast<long long>(a.sessions) * b.max_sessions;
  const long long rhs = static_cast<long long>(b.sessions) * a.max_sessions;
  return std::tie(lhs, a.load, a.server_id) < std::tie(rhs, b.load, b.server_id);
}

/// The least loaded server with room (sessions < max_sessions), or none when every one
/// is full or the list is empty.
inline std::optional<ServerLoad> PickServer(const std::vector<ServerLoad>& servers) {
  std::optional<ServerLoad> best;
  for (const ServerLoad& s : servers) {
    if (s.max_sessions <= 0 || s.sessions >= s.max_sessions) continue;
    if (!best || PlaceBefore(s, *best)) best = s;
  }
  return best;
}

}  // namespace viscera::bus
