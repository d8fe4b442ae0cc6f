#pragma once
/// IoLoop: viscerad's one LCM I/O thread. It owns the bus's handling side, pumps it,
/// routes requests and poses to the SessionManager, and publishes the heartbeat.
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "bus/lcm_bus.h"
#include "server/capacity_estimate.h"
#include "server/heartbeat_source.h"
#include "server/peer_directory.h"
#include "server/server_config.h"
#include "server/session_manager.h"

namespace viscera::server {

class IoLoop {
 public:
  /// Opens the bus (so a bad URL fails here, before any thread starts) and subscribes.
  /// @throws InputError for a bad URL, server id, max_sessions, a period <= 0, or an
  ///         unreadable key file.
  explicit IoLoop(const ServerConfig& config);
  /// Stops the thread if it runs.
  ~IoLoop();
  IoLoop(const IoLoop&) = delete;
  IoLoop& operator=(const IoLoop&) = delete;

  /// Starts the I/O thread: a heartbeat at once, then one per period.
  /// @pre not started before.
  void Start();

  /// Asks the thread to stop and joins it (within one pump timeout, 100 ms), then stops
  /// every session (final status, records flushed). Idempotent.
  void Stop();

  /// Handles what waits on the bus, then finishes what is ready (creations, leases), on the
  /// calling thread: for tests and fuzzing, only while the I/O thread is not started.
  /// @return messages handled.
  int HandleWaiting();
  /// The bus requests and poses arrive on (with memq://, the only way in).
  bus::LcmBus& bus() { return *bus_; }
  /// Accept at most `max_sessions` sessions from now on (sessions running stay); the I/O
  /// thread applies it at its next turn (within 100 ms). Any thread. @pre max_sessions >= 1.
  void SetMaxSessions(int max_sessions);
  /// Admission by the measured cost (SessionManager::SetCapacity) from the next turn on, and
  /// its Describe() in every heartbeat. Any thread.
  void SetCapacity(const CapacityEstimate& estimate);
  /// Why the server holds what it holds, for the heartbeat (when not SetCapacity). Any thread.
  void SetCapacityNote(const std::string& note);

  /// True once the thread has died of an error; error() says which.
  bool failed() const { return failed_.load(); }
  std::string error() const;
  int64_t heartbeats_sent() const { return heartbeats_sent_.load(); }
  int num_sessions() const { return sessions_->num_sessions(); }
  int64_t rejected() const { return sessions_->rejected(); }

 private:
  void Run();

  ServerConfig config_;
  std::unique_ptr<bus::LcmBus> bus_;
  std::unique_ptr<bus::LcmBus> frame_bus_;    // publish only: frames (SessionManager says why)
  std::unique_ptr<SessionManager> sessions_;  // after the buses: sessions publish on them
  HeartbeatSource heartbeat_;
  PeerDirectory peers_;  // other servers' heartbeats, for refusals that name one with room
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<int> new_max_sessions_{0};  // 0: no change asked
  std::mutex capacity_mutex_;             // guards the two below, handed to the I/O thread
  std::optional<CapacityEstimate> new_capacity_;
  std::optional<std::string> new_capacity_note_;
  std::atomic<bool> failed_{false};
  std::atomic<int64_t> heartbeats_sent_{0};
  mutable std::mutex error_mutex_;
  std::string error_;
};

}  // namespace viscera::server
