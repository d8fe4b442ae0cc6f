#pragma once
/// Pacer: paces a fixed-rate loop by absolute deadlines (no drift), sleeping until shortly
/// before each deadline and spinning the rest of the way. On a shared machine a thread that
/// only sleeps wakes 0.1-1 ms late now and then; the spin absorbs that lateness at the cost of
/// spin_ns of CPU per period (docs/haptics.md, "Pacing", has the measurements behind the
/// default). Counts late wake-ups, missed deadlines and resynchronizations.
///
/// Threading: one thread (the loop's) calls everything.
#include <cstdint>
#include <functional>

namespace viscera {

/// The clock a Pacer reads and sleeps on: monotonic nanoseconds. Tests pass a fake one.
struct PacerClock {
  std::function<int64_t()> now;              ///< monotonic time (ns)
  std::function<void(int64_t)> sleep_until;  ///< sleeps until a monotonic time (ns)
  /// The system's CLOCK_MONOTONIC with clock_nanosleep.
  static PacerClock Monotonic();
};

/// The spin margin that paid off on this machine (docs/server-benchmarks.md, "Pacing"):
/// 50 us for a SCHED_FIFO thread (no peer preempts it, the spin absorbs the wake-up latency),
/// none under normal scheduling (a spinning thread spends its fair share and is preempted more
/// often: on the loaded 2-vCPU machine every margin made p99 and misses worse).
inline int64_t AutoSpinNs(bool realtime) { return realtime ? 50'000 : 0; }

struct PacerOptions {
  int64_t period_ns = 1'000'000;  ///< > 0
  /// Sleep until this long before each deadline, then spin (ns, >= 0; 0: sleep only).
  int64_t spin_ns = 200'000;
  /// A wake-up later than this after its deadline counts as late (ns, >= 0).
  int64_t late_ns = 50'000;
};

class Pacer {
 public:
  /// @throws InputError when period_ns <= 0 or spin_ns, late_ns < 0.
  explicit Pacer(PacerOptions options, PacerClock clock = PacerClock::Monotonic());

  /// The first deadline is now (or `first_deadline_ns` when given). Sets the calling thread's
  /// timer slack to 1 us (Linux batches a normal thread's wake-ups by up to 50 us otherwise):
  /// call it on the loop's thread.
  void Start();
  void Start(int64_t first_deadline_ns);

  /// Waits for the current deadline: sleeps until spin_ns before it, then spins.
  /// @return the time it woke (>= deadline(); later when the sleep overshot).
  int64_t Wait();

  /// The period's work ended at `done_ns`. Moves the deadline on by one period; after a stall
  /// longer than a period (a paused machine) starts again from `done_ns` rather than catching
  /// up with a burst. @return true when the work ended after the next deadline (a miss).
  bool Advance(int64_t done_ns);

  int64_t deadline() const { return deadline_; }
  int64_t period_ns() const { return options_.period_ns; }
  const PacerOptions& options() const { return options_; }
  /// How late the last Wait woke after its deadline (ns, >= 0).
  int64_t last_lateness_ns() const { return last_lateness_ns_; }

  int64_t periods() const { return periods_; }            ///< Waits so far
  int64_t late_wakeups() const { return late_wakeups_; }  ///< lateness > late_ns
  int64_t misses() const { return misses_; }              ///< Advance returned true
  int64_t resyncs() const { return resyncs_; }            ///< restarts after a stall

 private:
  PacerOptions options_;
  PacerClock clock_;
  int64_t deadline_ = 0;
  int64_t last_lateness_ns_ = 0;
  int64_t periods_ = 0, late_wakeups_ = 0, misses_ = 0, resyncs_ = 0;
};

}  // namespace viscera
