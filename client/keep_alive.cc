#include "client/keep_alive.h"

#include <pthread.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <utility>

#include "common/check.h"

namespace viscera::client {

double KeepAlivePeriod(double lease_s) {
  if (!(lease_s > 0.0)) return 15.0;
  return std::clamp(lease_s / 4.0, 0.2, 15.0);
}

KeepAlive::KeepAlive(SessionClient* client, int64_t session_id, std::vector<uint8_t> token,
                     double period_s)
    : KeepAlive(client, session_id, std::move(token), period_s,
                viscera_proto::session_request_t::kKeepAlive) {}

KeepAlive::KeepAlive(SessionClient* client, int64_t session_id, std::vector<uint8_t> token,
                     double period_s, int8_t command)
    : client_(client),
      session_id_(session_id),
      token_(std::move(token)),
      period_s_(period_s),
      command_(command) {
  VISCERA_DEMAND(client_ != nullptr && period_s_ > 0.0);
  if (token_.empty() && command_ != viscera_proto::session_request_t::kWatchFrames) return;
  // The thread takes no signals (it inherits the mask): SIGINT/SIGTERM stay with the
  // threads that handle them (viscera view waits for them synchronously).
  sigset_t all, old;
  sigfillset(&all);
  pthread_sigmask(SIG_BLOCK, &all, &old);
  thread_ = std::thread([this] { Run(); });
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
}

KeepAlive::~KeepAlive() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

int64_t KeepAlive::sent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sent_;
}

void KeepAlive::Run() {
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(period_s_));
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    lock.unlock();
    viscera_proto::session_request_t request = MakeRequest(command_, session_id_);
    request.header.token = token_;
    request.header.token_len = static_cast<int32_t>(token_.size());
    const bool ok = client_->Send(&request);
    lock.lock();
    if (ok) ++sent_;
    wake_.wait_for(lock, period, [this] { return stop_; });
  }
}

}  // namespace viscera::client
