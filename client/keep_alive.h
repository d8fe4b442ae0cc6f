#pragma once
/// KeepAlive: keeps a session's lease renewed while a client uses it (docs/security.md,
/// "Session leases"). A thread of its own sends a kKeepAlive request with the session's
/// token every period; it never waits for the reply, so it works next to any loop that
/// pumps the same bus (or none). Used by `viscera drive`, `view`, `record`, `frames`; other
/// clients (the haptic bridge) hold one the same way.
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "client/session_client.h"

namespace viscera::client {

/// A keep-alive period that renews a lease of `lease_s` (from session_status_t.lease_s;
/// 0 = unknown or none) several times before it runs out: a quarter of it, 0.2..15 s.
double KeepAlivePeriod(double lease_s);

/// How often a client that takes frames renews the session's frame lease (s): well within
/// viscerad's default --frame-lease of 5 s.
inline constexpr double kFrameWatchPeriodS = 1.0;

class KeepAlive {
 public:
  /// Starts sending at once, then every `period_s` (> 0). An empty token sends nothing (a
  /// viewer without the token cannot renew the lease, and says so to its user).
  /// @pre client outlives this object.
  KeepAlive(SessionClient* client, int64_t session_id, std::vector<uint8_t> token, double period_s);
  /// Sends `command` instead: kWatchFrames renews the session's frame lease, token or not (a
  /// client that takes the session's frames).
  KeepAlive(SessionClient* client, int64_t session_id, std::vector<uint8_t> token, double period_s,
            int8_t command);
  /// Stops the thread (at once, not after a period).
  ~KeepAlive();
  KeepAlive(const KeepAlive&) = delete;
  KeepAlive& operator=(const KeepAlive&) = delete;

  int64_t sent() const;

 private:
  void Run();

  SessionClient* client_;
  int64_t session_id_;
  std::vector<uint8_t> token_;
  double period_s_;
  int8_t command_ = viscera_proto::session_request_t::kKeepAlive;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  int64_t sent_ = 0;
  std::thread thread_;
};

}  // namespace viscera::client
