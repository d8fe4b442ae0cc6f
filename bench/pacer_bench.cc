// Pacing benchmark (docs/benchmarks.md, "Haptics"): a 1 kHz loop paced by common/pacer.h
// with several spin margins, doing nothing but waiting, on this (shared) machine. Prints, per
// margin: period error p50/p99/max (|actual - nominal| between consecutive wake-ups), deadline
// misses, late wake-ups (> 50 us), and the CPU the loop thread used (fraction of one core).
// Usage: bench_pacer [SECONDS_PER_MARGIN] [RATE_HZ] [MARGIN_US ...]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "common/clock.h"
#include "common/pacer.h"
#include "common/quantile.h"

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 10.0;
  const double rate = argc > 2 ? std::atof(argv[2]) : 1000.0;
  std::vector<double> margins_us;
  for (int i = 3; i < argc; ++i) margins_us.push_back(std::atof(argv[i]));
  if (margins_us.empty()) margins_us = {0, 50, 100, 200, 400};
  const auto period = static_cast<int64_t>(std::llround(1e9 / rate));
  std::printf("%-9s %9s %9s %9s %8s %8s %6s\n", "spin_us", "err_p50", "err_p99", "err_max", "misses",
              "late", "cpu");
  for (const double margin : margins_us) {
    viscera::Pacer pacer({.period_ns = period, .spin_ns = static_cast<int64_t>(margin * 1e3)});
    const auto n = static_cast<int64_t>(seconds * rate);
    std::vector<double> error_us;
    error_us.reserve(static_cast<size_t>(n));
    const int64_t cpu0 = viscera::ThreadCpuNanos();
    pacer.Start();
    int64_t prev = 0;
    for (int64_t k = 0; k < n; ++k) {
      const int64_t wake = pacer.Wait();
      if (prev > 0) error_us.push_back(std::abs(static_cast<double>(wake - prev - period)) * 1e-3);
      prev = wake;
      pacer.Advance(viscera::MonotonicNanos());
    }
    const double cpu = static_cast<double>(viscera::ThreadCpuNanos() - cpu0) / (seconds * 1e9);
    double max = 0.0;
    for (const double e : error_us) max = std::max(max, e);
    std::printf("%-9.0f %9.1f %9.1f %9.0f %8lld %8lld %5.0f%%\n", margin, viscera::Quantile(error_us, 0.5),
                viscera::Quantile(error_us, 0.99), max, static_cast<long long>(pacer.misses()),
                static_cast<long long>(pacer.late_wakeups()), 100.0 * cpu);
    std::fflush(stdout);
  }
  return 0;
}
