#pragma once
/// Clocks: CPU time of the calling thread (for step costs) and monotonic wall time.
#include <cerrno>
#include <cstdint>
#include <ctime>

namespace viscera {

/// CPU time consumed by the calling thread, in nanoseconds. Unlike wall time it does
/// not count time this thread spent preempted on a busy machine.
inline int64_t ThreadCpuNanos() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

/// Monotonic wall time in nanoseconds.
inline int64_t MonotonicNanos() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

/// Sleeps until the monotonic time `monotonic_ns` (absolute, so periodic loops do not drift),
/// resuming after signals.
inline void SleepUntil(int64_t monotonic_ns) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(monotonic_ns / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(monotonic_ns % 1'000'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

}  // namespace viscera
