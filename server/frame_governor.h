#pragma once
/// FrameGovernor: how fast and how large a session's frames are drawn under load. A pure policy
/// fed with timings: when the render thread cannot keep up with its period, or the mechanics'
/// step slack runs short, it lowers the frame rate, then (at the lowest rate) the frame size;
/// when both have been comfortable for a while it climbs back one level at a time. Separate
/// thresholds to go down and up (hysteresis) and a count of consecutive frames before each
/// move keep it from oscillating.
#include <array>

namespace viscera::server {

struct FrameGovernorConfig {
  /// A frame is overloaded when it took more than this share of its period, or when the
  /// mechanics' slack (session::StepSlack: 1 - the 90th percentile step wall time / step period
  /// over the last status period) is below `slack_low`.
  double busy_high = 0.8;
  double slack_low = 0.1;
  /// A frame is calm when it took less than this share of the period the level above would
  /// have, and the slack is above `slack_high`.
  double busy_low = 0.5;
  double slack_high = 0.4;
  int overloaded_to_lower = 5;  ///< consecutive overloaded frames before going down a level
  int calm_to_raise = 25;       ///< consecutive calm frames before going up a level
};

/// One level: the share of the configured rate and of the configured size (each side).
struct FrameLevel {
  double rate = 1.0;
  double scale = 1.0;
};

/// Level 0 is the configured stream; each next one costs less: the rate first, then the size.
inline constexpr std::array<FrameLevel, 6> kFrameLevels = {
    {{1.0, 1.0}, {0.6, 1.0}, {0.4, 1.0}, {0.4, 0.75}, {0.4, 0.5}, {0.2, 0.5}}};

class FrameGovernor {
 public:
  explicit FrameGovernor(FrameGovernorConfig config = {}) : config_(config) {}

  /// Takes one frame's cost (ms of wall time: skin, draw and JPEG) at the current level's period
  /// `period_ms`, and the mechanics' step slack (1 - step wall time / step period; >= 1 when
  /// unknown). @return true when the level changed.
  bool Update(double frame_ms, double period_ms, double step_slack);

  int level() const { return level_; }
  const FrameLevel& current() const { return kFrameLevels[level_]; }

 private:
  FrameGovernorConfig config_;
  int level_ = 0;
  int overloaded_ = 0;
  int calm_ = 0;
};

}  // namespace viscera::server
