#pragma once
/// Whether a device loop held its rate, why not, and what to try: the last line of
/// `viscera haptic` (text and JSON). A pure function of the loop's summary.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "haptic/device_loop.h"

namespace viscera::client {

/// A loop holds its rate when it ran at least this share of it...
inline constexpr double kHeldRateShare = 0.99;
/// ...and at most this share of its periods missed their deadline (an isolated late period
/// is absorbed by the local model and the passivity controller; a steady 1 % is felt).
inline constexpr double kHeldMissShare = 0.01;

struct HapticVerdict {
  bool held = false;
  std::vector<std::string> why;    ///< the figures past the limits (empty when held)
  std::vector<std::string> tries;  ///< what to try, most effective first (empty when held)
  std::string line;                ///< one line: "held 1000 Hz: ..." or "did NOT hold ..."
};

/// The verdict on `s`, for a machine with `cores` CPUs usable by the client.
HapticVerdict JudgeHapticLoop(const haptic::LoopSummary& s, int cores);

nlohmann::ordered_json HapticVerdictToJson(const HapticVerdict& v);

}  // namespace viscera::client
