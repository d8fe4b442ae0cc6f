#pragma once
/// How `viscera` prints session status: JSON objects for scripts, aligned tables for people.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <viscera_proto/session_status_t.hpp>

namespace viscera::client {

/// "running", "paused", "faulted", "stopped" or "unknown(N)".
std::string StateName(int8_t state);

/// Keys, in order: session, server_id, scene, state, sim_time (s), steps, rate_hz (achieved,
/// Hz), configured_rate_hz, deadline_misses, jitter_p99_us, step_cost_p50_us,
/// step_cost_p99_us, step_wall_max_us, contacts, energy (J), tools, poses, rejected, replayed,
/// lease_s, lease_left_s, recoveries, idle_events, messages_dropped, nonfinite_dropped,
/// record_failures, unconverged_solves, target_exposed, running (running the bowel: coverage
/// 0..1, missed, grasps, slips, damage_events, damaged; null without [running]), frames,
/// last_error.
nlohmann::ordered_json StatusToJson(const viscera_proto::session_status_t& s);

/// A header line and one line per session (UNCONV: unconverged_solves).
std::string StatusTable(const std::vector<viscera_proto::session_status_t>& sessions);

}  // namespace viscera::client
