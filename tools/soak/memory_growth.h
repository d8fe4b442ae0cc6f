#pragma once
// The soak's memory verdict (docs/reliability.md): does the server's RSS stay within a bound once
// it is warm? Warm is counted in cycles, not in time, so that a loaded machine, which fits fewer
// cycles into the same seconds, does not take the baseline while the server is still growing to
// its working size.
#include <cstdint>
#include <span>
#include <string>

namespace viscera::soak {

/// The server's RSS at the end of one soak cycle.
struct RssSample {
  int64_t cycle = 0;     ///< 1-based
  double seconds = 0.0;  ///< since the soak started
  int64_t rss_kb = 0;
};

struct GrowthPolicy {
  int64_t warm_cycles = 0;    ///< the baseline is taken no earlier than the end of this cycle...
  double warm_seconds = 0.0;  ///< ...and no earlier than this many seconds into the run
  int64_t judged_cycles = 0;  ///< cycles after the baseline a verdict needs
  double bound_mb = 16.0;     ///< largest growth allowed from the baseline to the last sample
};

struct GrowthVerdict {
  enum class Outcome {
    kTooShort,  ///< no baseline yet, or fewer cycles after it than the policy needs: no verdict
    kFlat,      ///< growth within the bound
    kGrew,      ///< growth beyond the bound
  };
  Outcome outcome = Outcome::kTooShort;
  RssSample baseline{};       ///< cycle 0 when there is none
  RssSample last{};           ///< the series' last sample
  int64_t judged_cycles = 0;  ///< last.cycle - baseline.cycle
  double growth_mb = 0.0;     ///< last.rss_kb - baseline.rss_kb, in MB
  std::string message;        ///< the verdict with its counts, for a person
};

/// Judges a series of samples in rising cycle order: the baseline is its first sample at or after
/// both warm marks, the growth is from there to its last sample.
GrowthVerdict JudgeGrowth(std::span<const RssSample> series, const GrowthPolicy& policy);

}  // namespace viscera::soak
