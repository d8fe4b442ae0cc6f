#include "client/status_format.h"

#include <cmath>
#include <cstdio>

#include "client/printable.h"

namespace viscera::client {

using viscera_proto::session_status_t;

std::string StateName(int8_t state) {
  switch (state) {
    case session_status_t::kRunning: return "running";
    case session_status_t::kPaused: return "paused";
    case session_status_t::kFaulted: return "faulted";
    case session_status_t::kStopped: return "stopped";
    default: return "unknown(" + std::to_string(state) + ")";
  }
}

nlohmann::ordered_json StatusToJson(const session_status_t& s) {
  // the targets' exposure (the full assessment: viscera report)
  nlohmann::ordered_json targets = nlohmann::ordered_json::object();
  for (size_t i = 0; i < static_cast<size_t>(s.num_targets) && i < s.target_exposed.size(); ++i) {
    targets[s.target_names[i]] = s.target_exposed[i];
  }
  // running the bowel's figures (the whole score: viscera report); null without [running]
  nlohmann::ordered_json running = nullptr;
  if (s.running_segments > 0) {
    running = {{"coverage", s.running_coverage},
               {"missed", s.running_missed},
               {"grasps", s.running_grasps},
               {"slips", s.running_slips},
               {"damage_events", s.running_num_events},
               {"damaged", s.running_damaged}};
  }
  return {{"session", s.header.session_id},
          {"server_id", s.server_id},
          {"scene", s.scene},
          {"state", StateName(s.state)},
          {"sim_time", s.sim_time},
          {"steps", s.steps},
          {"rate_hz", s.achieved_rate_hz},
          {"configured_rate_hz", s.rate_hz},
          {"deadline_misses", s.deadline_misses},
          {"jitter_p99_us", s.jitter_p99_us},
          {"step_cost_p50_us", s.step_cost_p50_us},
          {"step_cost_p99_us", s.step_cost_p99_us},
          {"step_wall_max_us", s.step_wall_max_us},
          {"contacts", s.contacts},
          {"energy", s.energy},
          {"tools", s.tool_names},
          {"poses", s.poses},
          {"rejected", s.rejected},
          {"replayed", s.replayed},
          {"lease_s", s.lease_s},
          {"lease_left_s", s.lease_left_s},
          {"recoveries", s.recoveries},
          {"idle_events", s.idle_events},
          {"messages_dropped", s.messages_dropped},
          {"nonfinite_dropped", s.nonfinite_dropped},
          {"record_failures", s.record_failures},
          {"unconverged_solves", s.unconverged_solves},
          {"target_exposed", targets},
          {"running", running},
          {"frames",
           {{"skin", s.skin},
            {"size", std::to_string(s.frame_width) + "x" + std::to_string(s.frame_height)},
            {"rate_hz", s.achieved_frame_rate_hz},
            {"configured_rate_hz", s.frame_rate_hz},
            {"sent", s.frames},
            {"dropped", s.frames_dropped},
            {"skin_ms", s.skin_ms},
            {"render_ms", s.render_ms},
            {"encode_ms", s.encode_ms},
            {"bytes", s.frame_bytes}}},
          {"last_error", s.last_error}};
}

// A rate or time from the wire rounded for the table; a hostile value (NaN, inf, 1e252) is printed
// as it is: converting it to int would be undefined behaviour.
static std::string Whole(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), std::isfinite(v) && std::fabs(v) < 1e9 ? "%.0f" : "%.3g", v);
  return text;
}

// Running the bowel's coverage for the table: "88.9%", "-" without [running]; a hostile value
// (NaN, inf, 1e252) as it is.
static std::string Coverage(const session_status_t& s) {
  if (s.running_segments <= 0) return "-";
  const double percent = 100.0 * s.running_coverage;
  char text[32];
  std::snprintf(text, sizeof(text),
                std::isfinite(percent) && std::fabs(percent) < 1e9 ? "%.1f%%" : "%.3g", percent);
  return text;
}

std::string StatusTable(const std::vector<session_status_t>& sessions) {
  // the running column only when a session runs the bowel ([running]): coverage, % of segments
  bool running = false;
  for (const session_status_t& s : sessions) running = running || s.running_segments > 0;
  std::string out;
  char line[768];
  char column[16] = "";  // right-aligned like the values below it
  if (running) std::snprintf(column, sizeof(column), " %8s", "RUNNING");
  std::snprintf(line, sizeof(line), "%-17s %-12s %-8s %9s %14s %7s %9s %7s %9s %8s %7s %7s%s  %s\n",
                "SESSION", "SCENE", "STATE", "SIM_TIME", "RATE_HZ", "MISSES", "P99_US", "FPS",
                "REJECTED", "RECOVER", "UNCONV", "LEASE", column, "LAST_ERROR");
  out += line;
  for (const session_status_t& s : sessions) {
    const std::string rate = Whole(s.achieved_rate_hz) + "/" + Whole(s.rate_hz);
    const std::string fps =
        s.frame_rate_hz > 0 ? Whole(s.achieved_frame_rate_hz) + "/" + Whole(s.frame_rate_hz) : "-";
    const std::string lease = s.lease_s > 0 ? Whole(s.lease_left_s) + "s" : "-";
    char coverage[40] = "";
    if (running) std::snprintf(coverage, sizeof(coverage), " %8s", Coverage(s).c_str());
    std::snprintf(line, sizeof(line),
                  "%-17lld %-12s %-8s %8.2fs %14s %7lld %9.1f %7s %9lld %8lld %7lld %7s%s  %s\n",
                  static_cast<long long>(s.header.session_id), Printable(s.scene).c_str(),
                  StateName(s.state).c_str(), s.sim_time, rate.c_str(),
                  static_cast<long long>(s.deadline_misses), s.step_cost_p99_us, fps.c_str(),
                  static_cast<long long>(s.rejected), static_cast<long long>(s.recoveries),
                  static_cast<long long>(s.unconverged_solves), lease.c_str(), coverage,
                  Printable(s.last_error).c_str());
    out += line;
  }
  return out;
}

}  // namespace viscera::client
