#include "tools/soak/memory_growth.h"

#include <cstdio>

namespace viscera::soak {

namespace {

std::string Format(const char* format, auto... values) {
  char text[512];
  std::snprintf(text, sizeof text, format, values...);
  return text;
}

}  // namespace

GrowthVerdict JudgeGrowth(std::span<const RssSample> series, const GrowthPolicy& policy) {
  GrowthVerdict v;
  if (!series.empty()) v.last = series.back();
  for (const RssSample& s : series) {
    if (s.cycle >= policy.warm_cycles && s.seconds >= policy.warm_seconds) {
      v.baseline = s;
      break;
    }
  }
  if (v.baseline.cycle == 0) {
    v.message = Format(
        "too short to judge: no baseline yet (it needs cycle >= %lld and %.1f s; the run reached "
        "cycle %lld at %.1f s)",
        static_cast<long long>(policy.warm_cycles), policy.warm_seconds,
        static_cast<long long>(v.last.cycle), v.last.seconds);
    return v;
  }
  v.judged_cycles = v.last.cycle - v.baseline.cycle;
  v.growth_mb = static_cast<double>(v.last.rss_kb - v.baseline.rss_kb) / 1024.0;
  if (v.judged_cycles < policy.judged_cycles) {
    v.message =
        Format("too short to judge: %lld cycles after the baseline (cycle %lld), %lld needed",
               static_cast<long long>(v.judged_cycles), static_cast<long long>(v.baseline.cycle),
               static_cast<long long>(policy.judged_cycles));
    return v;
  }
  v.outcome = v.growth_mb <= policy.bound_mb ? GrowthVerdict::Outcome::kFlat
                                             : GrowthVerdict::Outcome::kGrew;
  v.message =
      Format("RSS %+.1f MB from cycle %lld (%.1f MB) to cycle %lld (%.1f MB), bound %.1f MB: %s",
             v.growth_mb, static_cast<long long>(v.baseline.cycle), v.baseline.rss_kb / 1024.0,
             static_cast<long long>(v.last.cycle), v.last.rss_kb / 1024.0, policy.bound_mb,
             v.outcome == GrowthVerdict::Outcome::kFlat ? "within" : "beyond");
  return v;
}

}  // namespace viscera::soak
