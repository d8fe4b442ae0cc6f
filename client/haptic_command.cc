#include "client/haptic_command.h"

#include <sched.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <memory>

#include "client/haptic_verdict.h"
#include "common/check.h"
#include "haptic/lcm_link.h"
#include "haptic/replay_device.h"

namespace viscera::client {

namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

// CPUs this process may run on (its affinity mask), for the verdict's advice.
int UsableCores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  return sched_getaffinity(0, sizeof(set), &set) == 0 ? CPU_COUNT(&set) : 1;
}

void PrintLive(const haptic::LoopReport& r) {
  std::fprintf(
      stderr,
      "\r%7.1f s  %6.0f Hz  period err p99 %5.0f us  misses %lld  round trip p50 %6.0f us  "
      "model age %6.1f ms  |F| %5.2f N  gain %.2f ",
      r.t_s, r.rate_hz, r.period_error_p99_us, static_cast<long long>(r.misses),
      r.round_trip_p50_us, r.model_age_ms, r.force_n, r.gain);
}

void PrintSummary(const HapticCommand& c, const haptic::LoopSummary& s) {
  std::printf(
      "haptic loop on session %lld tool %s, device %s: %.2f s, %.1f of %.0f Hz (realtime %s)\n",
      static_cast<long long>(c.session_id), c.tool_name.c_str(), s.device.c_str(), s.duration_s,
      s.achieved_rate_hz, s.rate_hz, s.realtime.c_str());
  std::printf(
      "period     error p50 %.1f us, p99 %.1f us, max %.0f us; %lld misses, %lld late wake-ups of "
      "%lld\n",
      s.period_error_p50_us, s.period_error_p99_us, s.period_error_max_us,
      static_cast<long long>(s.misses), static_cast<long long>(s.late_wakeups),
      static_cast<long long>(s.periods));
  std::printf(
      "round trip pose -> force p50 %.0f us, p99 %.0f us (%lld poses answered); model age p50 %.1f "
      "ms, p99 %.1f ms\n",
      s.round_trip_p50_us, s.round_trip_p99_us, static_cast<long long>(s.round_trips),
      s.model_age_p50_ms, s.model_age_p99_ms);
  std::printf(
      "messages   %lld poses sent (%lld lost by impairment), %lld answers (%lld used, %lld out of "
      "order, %lld lost)\n",
      static_cast<long long>(s.poses_sent), static_cast<long long>(s.poses_lost),
      static_cast<long long>(s.answers_received), static_cast<long long>(s.answers_accepted),
      static_cast<long long>(s.answers_out_of_order), static_cast<long long>(s.answers_lost));
  std::printf(
      "force      peak %.3f N (limit %.2f N, %.0f N/s), %lld clamped, %lld rate-limited, K cap "
      "%.0f N/m\n",
      s.peak_force_n, s.max_force_n, s.max_force_rate_n_s, static_cast<long long>(s.force_clamped),
      static_cast<long long>(s.rate_limited), s.max_stiffness_n_m);
  std::printf(
      "events     %lld stale fades, %lld non-finite; passivity %s: energy %.3g J (min %.3g J), "
      "dissipated %.3g J in %lld periods\n",
      static_cast<long long>(s.fade_events), static_cast<long long>(s.nonfinite_events),
      s.passivity ? "on" : "OFF (observer only)", s.energy_j, s.min_energy_j, s.dissipated_j,
      static_cast<long long>(s.passivity_activations));
}

}  // namespace

nlohmann::ordered_json HapticSummaryToJson(const haptic::LoopSummary& s) {
  return {{"device", s.device},
          {"duration_s", s.duration_s},
          {"rate_hz", s.rate_hz},
          {"achieved_rate_hz", s.achieved_rate_hz},
          {"periods", s.periods},
          {"period_error_p50_us", s.period_error_p50_us},
          {"period_error_p99_us", s.period_error_p99_us},
          {"period_error_max_us", s.period_error_max_us},
          {"deadline_misses", s.misses},
          {"late_wakeups", s.late_wakeups},
          {"resyncs", s.resyncs},
          {"realtime", s.realtime},
          {"round_trip_p50_us", s.round_trip_p50_us},
          {"round_trip_p99_us", s.round_trip_p99_us},
          {"round_trips", s.round_trips},
          {"model_age_p50_ms", s.model_age_p50_ms},
          {"model_age_p99_ms", s.model_age_p99_ms},
          {"poses_sent", s.poses_sent},
          {"poses_lost", s.poses_lost},
          {"answers_received", s.answers_received},
          {"answers_accepted", s.answers_accepted},
          {"answers_out_of_order", s.answers_out_of_order},
          {"answers_unmatched", s.answers_unmatched},
          {"messages_lost", s.answers_lost},
          {"link_rejected", s.link_rejected},
          {"peak_force_n", s.peak_force_n},
          {"max_force_n", s.max_force_n},
          {"max_force_rate_n_s", s.max_force_rate_n_s},
          {"max_stiffness_n_m", s.max_stiffness_n_m},
          {"force_clamped", s.force_clamped},
          {"rate_limited", s.rate_limited},
          {"stiffness_capped", s.stiffness_capped},
          {"nonfinite_events", s.nonfinite_events},
          {"fade_events", s.fade_events},
          {"passivity", s.passivity},
          {"energy_j", s.energy_j},
          {"min_energy_j", s.min_energy_j},
          {"dissipated_j", s.dissipated_j},
          {"passivity_activations", s.passivity_activations}};
}

int RunHaptic(SessionClient& client, const HapticCommand& c) {
  std::unique_ptr<haptic::Device> device;
  if (c.device == "sim") {
    ThrowUnless(!c.script.empty(),
                "--device sim needs --script FILE.csv (the hand's intended path)");
    device = std::make_unique<haptic::SimDevice>(script::ToolScript::Load(c.script), c.tool_name,
                                                 c.hand);
  } else if (c.device == "replay") {
    ThrowUnless(!c.replay_log.empty(),
                "--device replay needs --replay FILE.jsonl (a --log of an earlier run)");
    device = std::make_unique<haptic::ReplayDevice>(
        haptic::ReplayDevice::Load(c.replay_log, c.hand.limits));
  } else {
    Fail("unknown device '", c.device, "' (known: sim, replay)");
  }

  std::unique_ptr<std::FILE, int (*)(std::FILE*)> log(nullptr, &std::fclose);
  std::vector<char> log_buffer;
  haptic::DeviceLoopOptions options = c.loop;
  if (!c.log_path.empty()) {
    log.reset(std::fopen(c.log_path.c_str(), "w"));
    ThrowUnless(log != nullptr, "cannot write the log '", c.log_path, "'");
    // a large buffer: the loop's thread writes a line per period, the kernel sees few writes
    log_buffer.resize(size_t{4} << 20);
    std::setvbuf(log.get(), log_buffer.data(), _IOFBF, log_buffer.size());
    options.log = log.get();
  }
  if (c.live) options.on_report = PrintLive;
  g_stop = false;
  options.stop = &g_stop;
  auto previous_int = std::signal(SIGINT, OnSignal);
  auto previous_term = std::signal(SIGTERM, OnSignal);

  haptic::LcmLink link(&client.bus(), c.session_id, c.token, c.tool);
  haptic::DeviceLoop loop(device.get(), &link, options);
  const haptic::LoopSummary s = loop.Run();
  std::signal(SIGINT, previous_int);
  std::signal(SIGTERM, previous_term);
  if (c.live) std::fputc('\n', stderr);
  log.reset();  // flushed before the summary says it is there

  const HapticVerdict verdict = JudgeHapticLoop(s, UsableCores());
  if (c.json) {
    nlohmann::ordered_json j = {{"session", c.session_id}, {"tool", c.tool_name}};
    j["haptic"] = HapticSummaryToJson(s);
    j["verdict"] = HapticVerdictToJson(verdict);
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    PrintSummary(c, s);
    std::printf("verdict    %s\n", verdict.line.c_str());
  }
  if (s.answers_received == 0) {
    std::fprintf(stderr, "viscera: no force answer received from session %lld\n",
                 static_cast<long long>(c.session_id));
    return 2;
  }
  return 0;
}

}  // namespace viscera::client
