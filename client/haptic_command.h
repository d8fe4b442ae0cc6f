#pragma once
/// `viscera haptic SESSION --tool NAME --device BACKEND ...`: wires a device backend and the
/// session's force channel to the haptic device loop (src/haptic) and prints its figures.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "client/session_client.h"
#include "haptic/device_loop.h"
#include "haptic/sim_device.h"

namespace viscera::client {

struct HapticCommand {
  int64_t session_id = 0;
  std::vector<uint8_t> token;
  int tool = 0;  ///< index in the session's tools
  std::string tool_name;
  std::string device = "sim";   ///< sim | replay
  std::string script;           ///< sim: the hand's intended path (tool-script CSV)
  std::string replay_log;       ///< replay: a --log JSONL file
  haptic::SimHandOptions hand;  ///< sim: the hand and the simulated device's limits
  haptic::DeviceLoopOptions loop;
  std::string log_path;  ///< --log FILE.jsonl ("" none)
  bool json = false;
  bool live = false;  ///< the live report on stderr
};

/// Exit codes: 0 done, 1 local error (bad file or option), 2 no answer from the server.
int RunHaptic(SessionClient& client, const HapticCommand& command);

nlohmann::ordered_json HapticSummaryToJson(const haptic::LoopSummary& s);

}  // namespace viscera::client
