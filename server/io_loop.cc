#include "server/io_loop.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <utility>

#include "bus/channels.h"
#include "common/check.h"
#include "common/clock.h"

namespace viscera::server {
namespace {

// Longest wait inside LCM: bounds how late the loop notices Stop().
constexpr std::chrono::milliseconds kMaxPump{100};
// A peer not heard for three heartbeat periods is gone.
constexpr int kPeerLifetimePeriods = 3;

}  // namespace

IoLoop::IoLoop(const ServerConfig& config)
    : config_(config),
      heartbeat_(config.server_id, config.max_sessions),
      peers_(config.server_id,
             std::chrono::nanoseconds(config.heartbeat_period * kPeerLifetimePeriods).count()) {
  ThrowUnless(config_.heartbeat_period.count() > 0, "heartbeat period must be > 0 ms, got ",
              config_.heartbeat_period.count());
  ThrowUnless(config_.status_rate_hz > 0.0 && config_.max_rate_hz >= 1.0,
              "status rate and max rate must be positive");
  ThrowUnless(config_.max_clock_skew_s > 0.0, "clock-skew bound must be > 0 s");
  bus_ = std::make_unique<bus::LcmBus>(config_.lcm_url);
  if (config_.max_message_bytes > 0) bus_->SetMaxMessageSize(config_.max_message_bytes);
  frame_bus_ = std::make_unique<bus::LcmBus>(config_.lcm_url);
  if (!config_.key_file.empty()) {
    auto auth = std::make_shared<bus::MessageAuth>(bus::MessageAuth::FromKeyFile(config_.key_file));
    bus_->SetAuth(auth);
    frame_bus_->SetAuth(auth);
  }
  sessions_ = std::make_unique<SessionManager>(config_, bus_.get(), frame_bus_.get());
  sessions_->SetPeers(&peers_);
  // subscribed here, before the thread pumps: LCM 1.3.1 must not subscribe while dispatching
  bus_->SetDropHandler([this](const std::string& channel, bus::DropReason reason,
                              const uint8_t* data,
                              int size) { sessions_->OnDrop(channel, reason, data, size); });
  bus_->SubscribeWithInfo<viscera_proto::session_request_t>(
      bus::kRequestChannel,
      [this](const viscera_proto::session_request_t& msg, const bus::MessageInfo& info) {
        sessions_->OnRequest(msg, info);
      });
  bus_->Subscribe<viscera_proto::heartbeat_t>(
      bus::kHeartbeatChannel, [this](const viscera_proto::heartbeat_t& msg, int64_t) {
        peers_.Observe(msg, MonotonicNanos());
      });
  bus_->SubscribeWithInfo<viscera_proto::tool_pose_t>(
      std::string(bus::kPosePrefix) + "[0-9]+",
      [this](const viscera_proto::tool_pose_t& msg, const bus::MessageInfo& info) {
        sessions_->OnPose(msg, info);
      });
}

IoLoop::~IoLoop() { Stop(); }

void IoLoop::Start() {
  VISCERA_DEMAND(!thread_.joinable());
  thread_ = std::thread([this] { Run(); });
}

int IoLoop::HandleWaiting() {
  VISCERA_DEMAND(!thread_.joinable());
  const int handled = bus_->Drain();
  sessions_->Poll();
  return handled;
}

void IoLoop::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  sessions_->StopAll();
}

void IoLoop::SetMaxSessions(int max_sessions) {
  VISCERA_DEMAND(max_sessions >= 1);
  new_max_sessions_ = max_sessions;
}

void IoLoop::SetCapacity(const CapacityEstimate& estimate) {
  std::lock_guard<std::mutex> lock(capacity_mutex_);
  new_capacity_ = estimate;
  new_capacity_note_ = estimate.Describe();
}

void IoLoop::SetCapacityNote(const std::string& note) {
  std::lock_guard<std::mutex> lock(capacity_mutex_);
  new_capacity_note_ = note;
}

std::string IoLoop::error() const {
  std::lock_guard<std::mutex> lock(error_mutex_);
  return error_;
}

void IoLoop::Run() {
  using Clock = std::chrono::steady_clock;
  if (config_.realtime_priority > 0) {
    // poses wait for this thread: it runs at the mechanics threads' priority
    sched_param param{};
    param.sched_priority = config_.realtime_priority;
    if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) != 0) {
      std::fprintf(stderr, "viscerad: realtime priority refused for the I/O thread\n");
    }
  }
  // An exception never crosses a thread: record it and let main decide.
  try {
    auto next_heartbeat = Clock::now();
    while (!stop_.load()) {
      if (const int n = new_max_sessions_.exchange(0); n > 0) {
        sessions_->SetMaxSessions(n);
        heartbeat_.SetMaxSessions(n);
      }
      if (std::unique_lock<std::mutex> lock(capacity_mutex_, std::try_to_lock); lock.owns_lock()) {
        if (new_capacity_) {
          sessions_->SetCapacity(*new_capacity_);
          heartbeat_.SetMaxSessions(new_capacity_->max_sessions);
          new_capacity_.reset();
        }
        if (new_capacity_note_)
          heartbeat_.SetCapacityNote(*std::exchange(new_capacity_note_, std::nullopt));
      }
      const auto now = Clock::now();
      if (now >= next_heartbeat) {
        viscera_proto::heartbeat_t heartbeat =
            heartbeat_.Next(sessions_->num_sessions(), sessions_->rejected());
        heartbeat.replayed = sessions_->replayed();
        heartbeat.cores = AvailableCores();
        heartbeat.not_ours = sessions_->not_ours();
        heartbeat.unconverged_solves = sessions_->unconverged_solves();
        PutLimits(config_, &heartbeat);
        if (bus_->Publish(bus::kHeartbeatChannel, heartbeat)) {
          ++heartbeats_sent_;
        }
        // absolute schedule, but never a burst of catch-up heartbeats after a stall
        next_heartbeat = std::max(next_heartbeat + config_.heartbeat_period, now);
      }
      const auto wait =
          std::chrono::duration_cast<std::chrono::milliseconds>(next_heartbeat - Clock::now());
      // while a model is being built elsewhere, look for it often
      const auto longest = sessions_->creating() ? std::chrono::milliseconds{5} : kMaxPump;
      bus_->Pump(static_cast<int>(std::clamp(wait, std::chrono::milliseconds{0}, longest).count()));
      sessions_->Poll();
    }
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> lock(error_mutex_);
    error_ = e.what();
    failed_ = true;
  }
}

}  // namespace viscera::server
