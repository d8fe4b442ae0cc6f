#pragma once
/// IoLoop: viscerad's one LCM I/O thread. It owns the bus's handling side, pumps it,
/// and publishes the heartbeat. Later issues add session routing here.
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "bus/lcm_bus.h"
#include "server/heartbeat_source.h"

namespace viscera::server {

struct ServerConfig {
  std::string lcm_url;        ///< LCM URL, already resolved (bus::ResolveUrl)
  std::string server_id;      ///< name announced in heartbeats
  int max_sessions = 4;       ///< sessions accepted at most
  std::chrono::milliseconds heartbeat_period{1000};
};

class IoLoop {
 public:
  /// Opens the bus (so a bad URL fails here, before any thread starts).
  /// @throws InputError for a bad URL, server id, max_sessions or a period <= 0.
  explicit IoLoop(const ServerConfig& config);
  /// Stops the thread if it runs.
  ~IoLoop();
  IoLoop(const IoLoop&) = delete;
  IoLoop& operator=(const IoLoop&) = delete;

  /// Starts the I/O thread: a heartbeat at once, then one per period.
  /// @pre not started before.
  void Start();

  /// Asks the thread to stop and joins it (within one pump timeout, 100 ms).
  /// Idempotent.
  void Stop();

  /// True once the thread has died of an error; error() says which.
  bool failed() const { return failed_.load(); }
  std::string error() const;
  int64_t heartbeats_sent() const { return heartbeats_sent_.load(); }

 private:
  void Run();

  ServerConfig config_;
  std::unique_ptr<bus::LcmBus> bus_;
  HeartbeatSource heartbeat_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> failed_{false};
  std::atomic<int64_t> heartbeats_sent_{0};
  mutable std::mutex error_mutex_;
  std::string error_;
};

}  // namespace viscera::server
