#include "common/pacer.h"

#include <sys/prctl.h>

#include <utility>

#include "common/check.h"
#include "common/clock.h"

namespace viscera {

namespace {

// Tells the CPU this is a spin-wait: cheaper for the sibling hyper-thread, no syscall.
inline void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

}  // namespace

PacerClock PacerClock::Monotonic() { return {&MonotonicNanos, &SleepUntil}; }

Pacer::Pacer(PacerOptions options, PacerClock clock) : options_(options), clock_(std::move(clock)) {
  ThrowUnless(options_.period_ns > 0, "Pacer: period must be > 0 ns, got ", options_.period_ns);
  ThrowUnless(options_.spin_ns >= 0, "Pacer: spin must be >= 0 ns, got ", options_.spin_ns);
  ThrowUnless(options_.late_ns >= 0, "Pacer: late threshold must be >= 0 ns, got ",
              options_.late_ns);
  VISCERA_DEMAND(clock_.now && clock_.sleep_until);
}

void Pacer::Start() { Start(clock_.now()); }

void Pacer::Start(int64_t first_deadline_ns) {
  // Linux lets a normal thread's timed sleeps end up to 50 us late (timer slack) to batch
  // wake-ups; a loop that sleeps to a deadline wants 1 us. Per thread, no privilege needed.
  prctl(PR_SET_TIMERSLACK, 1000UL, 0UL, 0UL, 0UL);
  deadline_ = first_deadline_ns;
}

int64_t Pacer::Wait() {
  // sleep the bulk of the wait, then spin: a sleeping thread wakes late on a busy machine
  const int64_t sleep_until = deadline_ - options_.spin_ns;
  int64_t now = clock_.now();
  if (now < sleep_until) {
    clock_.sleep_until(sleep_until);
    now = clock_.now();
  }
  while (now < deadline_) {
    CpuRelax();
    now = clock_.now();
  }
  ++periods_;
  last_lateness_ns_ = now - deadline_;
  if (last_lateness_ns_ > options_.late_ns) ++late_wakeups_;
  return now;
}

bool Pacer::Advance(int64_t done_ns) {
  const int64_t next = deadline_ + options_.period_ns;
  const bool missed = done_ns > next;
  if (missed) ++misses_;
  deadline_ = next;
  // far behind (a stall, a paused machine): start again from now instead of a burst
  if (done_ns > deadline_ + options_.period_ns) {
    deadline_ = done_ns;
    ++resyncs_;
  }
  return missed;
}

}  // namespace viscera
