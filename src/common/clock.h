#pragma once
/// Clocks: CPU time of the calling thread (for step costs) and monotonic wall time.
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

}  // namespace viscera
