#include "client/haptic_verdict.h"

#include <cmath>

#include "common/check.h"

namespace viscera::client {
namespace {

std::string Percent(double share) { return Cat(std::round(share * 1000.0) / 10.0, " %"); }

}  // namespace

HapticVerdict JudgeHapticLoop(const haptic::LoopSummary& s, int cores) {
  HapticVerdict v;
  const double miss_share = s.periods > 0 ? static_cast<double>(s.misses) / s.periods : 1.0;
  const std::string rate = Cat(std::lround(s.rate_hz), " Hz");
  if (s.periods == 0) v.why.push_back("the loop ran no period");
  if (s.achieved_rate_hz < kHeldRateShare * s.rate_hz) {
    v.why.push_back(Cat("it ran at ", std::round(s.achieved_rate_hz * 10.0) / 10.0, " of ", rate));
  }
  if (s.periods > 0 && miss_share > kHeldMissShare) {
    v.why.push_back(Cat(Percent(miss_share), " of its periods missed their deadline (", s.misses,
                        " of ", s.periods, "; limit ", Percent(kHeldMissShare), ")"));
  }
  v.held = v.why.empty();
  if (v.held) {
    v.line =
        Cat("held ", rate, ": ", std::round(s.achieved_rate_hz * 10.0) / 10.0, " Hz, ", s.misses,
            s.misses == 1 ? " deadline miss" : " deadline misses", " in ", s.periods, " periods (",
            Percent(miss_share), ", limit ", Percent(kHeldMissShare), "), scheduling ", s.realtime);
    return v;
  }
  const bool fifo = s.realtime.rfind("SCHED_FIFO", 0) == 0;
  if (s.realtime == "off") {
    v.tries.push_back("--realtime 80 (SCHED_FIFO: as root, or with an rtprio limit: ulimit -r)");
  } else if (!fifo) {
    v.tries.push_back(
        Cat("--realtime was ", s.realtime,
            ": run as root or raise the rtprio limit (ulimit -r, /etc/security/limits.conf)"));
  }
  v.tries.push_back(
      cores <= 2 ? Cat("an isolated core: this machine has ", cores,
                       " core(s) shared by the server, its renderer and this client; "
                       "run the server elsewhere or pin it away (taskset)")
                 : "an isolated core (taskset -c N viscera haptic ..., isolcpus=N, or a cpuset) "
                   "with the server kept off it");
  std::string why, tries;
  for (const std::string& w : v.why) why += (why.empty() ? "" : "; ") + w;
  for (const std::string& t : v.tries) tries += (tries.empty() ? "" : ", or ") + t;
  v.line = Cat("did NOT hold ", rate, ": ", why, " (scheduling ", s.realtime, "); try ", tries);
  return v;
}

nlohmann::ordered_json HapticVerdictToJson(const HapticVerdict& v) {
  return {{"held", v.held}, {"why", v.why}, {"try", v.tries}, {"line", v.line}};
}

}  // namespace viscera::client
