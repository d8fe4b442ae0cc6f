#include "server/io_loop.h"

#include <algorithm>
#include <exception>

#include "bus/channels.h"
#include "common/check.h"

namespace viscera::server {
namespace {

// Longest wait inside LCM: bounds how late the loop notices Stop().
constexpr std::chrono::milliseconds kMaxPump{100};

}  // namespace

IoLoop::IoLoop(const ServerConfig& config)
    : config_(config), heartbeat_(config.server_id, config.max_sessions) {
  ThrowUnless(config_.heartbeat_period.count() > 0, "heartbeat period must be > 0 ms, got ",
              config_.heartbeat_period.count());
  bus_ = std::make_unique<bus::LcmBus>(config_.lcm_url);
}

IoLoop::~IoLoop() { Stop(); }

void IoLoop::Start() {
  VISCERA_DEMAND(!thread_.joinable());
  thread_ = std::thread([this] { Run(); });
}

void IoLoop::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

std::string IoLoop::error() const {
  std::lock_guard<std::mutex> lock(error_mutex_);
  return error_;
}

void IoLoop::Run() {
  using Clock = std::chrono::steady_clock;
  // An exception never crosses a thread: record it and let main decide.
  try {
    auto next_heartbeat = Clock::now();
    while (!stop_.load()) {
      const auto now = Clock::now();
      if (now >= next_heartbeat) {
        if (bus_->Publish(bus::kHeartbeatChannel, heartbeat_.Next(/*num_sessions=*/0))) {
          ++heartbeats_sent_;
        }
        // absolute schedule, but never a burst of catch-up heartbeats after a stall
        next_heartbeat = std::max(next_heartbeat + config_.heartbeat_period, now);
      }
      const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(
          next_heartbeat - Clock::now());
      bus_->Pump(static_cast<int>(std::clamp(wait, std::chrono::milliseconds{0}, kMaxPump).count()));
    }
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> lock(error_mutex_);
    error_ = e.what();
    failed_ = true;
  }
}

}  // namespace viscera::server
