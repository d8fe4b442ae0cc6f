#pragma once
/// Driver: streams a tool script to a session at a fixed pose rate (every scripted tool,
/// each tick) and collects the force feedback: force figures and the pose -> force round
/// trip (from the pose's send time to LCM's receive time of the first force message that
/// answers it).
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include <string>

#include "client/gesture.h"
#include "client/session_client.h"

namespace viscera::client {

struct DriveOptions {
  int64_t session_id = 0;
  std::vector<uint8_t> token;
  /// The session's tools in index order (session_status_t.tool_names); every tool of the
  /// script must be one of them.
  std::vector<std::string> tool_names;
  double pose_rate_hz = 100.0;  ///< poses per second
  double settle_s = 0.2;        ///< listen this long after the last pose
};

struct DriveResult {
  int64_t poses_sent = 0;
  int64_t forces_received = 0;
  int64_t poses_answered = 0;         ///< poses some force message echoed
  double max_force_n = 0.0;           ///< largest |F| over the tools (N)
  std::string tool_at_max;            ///< the tool that felt it
  double mean_force_n = 0.0;          ///< mean |F| over every force message (N)
  Vec3 force_at_max = Vec3::Zero();   ///< the force vector when |F| peaked (N)
  Vec3 tip_at_max = Vec3::Zero();     ///< simulated tip then (m)
  Vec3 target_at_max = Vec3::Zero();  ///< the pose target then (m)
  double round_trip_p50_us = 0.0;
  double round_trip_p99_us = 0.0;
  double round_trip_max_us = 0.0;
  int64_t clamped = 0;  ///< force messages with the clamp flag
  int64_t last_step = 0;
  double duration_s = 0.0;      ///< wall time driving (s)
  int reaches = 0;              ///< grasp rows reached again (ScriptPlayer)
  double script_delay_s = 0.0;  ///< how far those reaches set the script behind (s)
};

/// Drives `script` over its duration.
/// @throws InputError when the script names a tool the session does not have.
DriveResult Drive(SessionClient& client, const script::ToolScript& script,
                  const DriveOptions& options);

nlohmann::ordered_json DriveToJson(const DriveResult& r);

}  // namespace viscera::client
