// Pacing benchmark (docs/server-benchmarks.md, "Pacing"): a 1 kHz loop paced by common/pacer.h
// with several spin margins, doing nothing but waiting, on this (shared) machine. The margins
// take turns in one-second slices, so that a load that comes and goes falls on all of them
// alike. Prints, per margin: period error p50/p99/max (|actual - nominal| between consecutive
// wake-ups), deadline misses, late wake-ups (> 50 us), and the CPU the loop thread used
// (fraction of one core).
// Usage: bench_pacer [SECONDS_PER_MARGIN] [RATE_HZ] [MARGIN_US ...]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "common/clock.h"
#include "common/pacer.h"
#include "common/quantile.h"

namespace {

struct Figures {
  std::vector<double> error_us;
  int64_t misses = 0, late = 0, cpu_ns = 0, wall_ns = 0;
};

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 10.0;
  const double rate = argc > 2 ? std::atof(argv[2]) : 1000.0;
  std::vector<double> margins_us;
  for (int i = 3; i < argc; ++i) margins_us.push_back(std::atof(argv[i]));
  if (margins_us.empty()) margins_us = {0, 50, 100, 200, 400};
  const auto period = static_cast<int64_t>(std::llround(1e9 / rate));
  const auto slice = static_cast<int64_t>(rate);  // periods per one-second slice
  std::vector<Figures> figures(margins_us.size());
  for (int round = 0; round < static_cast<int>(std::ceil(seconds)); ++round) {
    for (size_t m = 0; m < margins_us.size(); ++m) {
      viscera::Pacer pacer(
          {.period_ns = period, .spin_ns = static_cast<int64_t>(margins_us[m] * 1e3)});
      Figures& f = figures[m];
      const int64_t cpu0 = viscera::ThreadCpuNanos(), wall0 = viscera::MonotonicNanos();
      pacer.Start();
      int64_t prev = 0;
      for (int64_t k = 0; k < slice; ++k) {
        const int64_t wake = pacer.Wait();
        if (prev > 0)
          f.error_us.push_back(std::abs(static_cast<double>(wake - prev - period)) * 1e-3);
        prev = wake;
        pacer.Advance(viscera::MonotonicNanos());
      }
      f.cpu_ns += viscera::ThreadCpuNanos() - cpu0;
      f.wall_ns += viscera::MonotonicNanos() - wall0;
      f.misses += pacer.misses();
      f.late += pacer.late_wakeups();
    }
  }
  std::printf("%-9s %9s %9s %9s %8s %8s %6s\n", "spin_us", "err_p50", "err_p99", "err_max",
              "misses", "late", "cpu");
  for (size_t m = 0; m < margins_us.size(); ++m) {
    const Figures& f = figures[m];
    double max = 0.0;
    for (const double e : f.error_us) max = std::max(max, e);
    std::printf("%-9.0f %9.1f %9.1f %9.0f %8lld %8lld %5.0f%%\n", margins_us[m],
                viscera::Quantile(f.error_us, 0.5), viscera::Quantile(f.error_us, 0.99), max,
                static_cast<long long>(f.misses), static_cast<long long>(f.late),
                100.0 * static_cast<double>(f.cpu_ns) / static_cast<double>(f.wall_ns));
  }
  return 0;
}
