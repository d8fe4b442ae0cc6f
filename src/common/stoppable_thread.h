#pragma once
/// A worker thread that paces itself and can be stopped between rounds: the server's frame
/// streamer and exposure watcher. The worker sleeps in SleepUntil, which a stop request wakes at
/// once, so Stop never waits out a period.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <utility>

#include "common/check.h"

namespace viscera {

class StoppableThread {
 public:
  StoppableThread() = default;
  StoppableThread(const StoppableThread&) = delete;
  StoppableThread& operator=(const StoppableThread&) = delete;
  ~StoppableThread() { Stop(); }

  /// Runs body() on a new thread. @pre not started.
  template <typename Body>
  void Start(Body&& body) {
    VISCERA_DEMAND(!thread_.joinable());
    thread_ = std::thread(std::forward<Body>(body));
  }
  /// Asks the body to stop at its next SleepUntil; returns at once.
  void RequestStop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
  }
  /// RequestStop, then waits for the thread. Idempotent.
  void Stop() {
    RequestStop();
    if (thread_.joinable()) thread_.join();
  }
  /// For the body: sleeps until the monotonic time `monotonic_ns` (MonotonicNanos's clock,
  /// CLOCK_MONOTONIC, which steady_clock is on Linux) or a stop request. False once asked to stop.
  bool SleepUntil(int64_t monotonic_ns) {
    std::unique_lock<std::mutex> lock(mutex_);
    return !wake_.wait_until(
        lock, std::chrono::steady_clock::time_point(std::chrono::nanoseconds(monotonic_ns)),
        [this] { return stop_; });
  }

 private:
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
};

}  // namespace viscera
