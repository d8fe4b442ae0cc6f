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
  /// A frame is overloaded when its own CPU time took more than this share of its period, when
  /// its wall time overran the period (the stream cannot keep its rate), or when the mechanics'
  /// slack (session::StepSlack: 1 - the 90th percentile step wall time / step period over the
  /// last status period) is below `slack_low`. Wall time alone would count the frames of other
  /// streams drawn on the same core meanwhile: two streams whose ticks coincide each see about
  /// twice their own cost, and both were lowered while the core had room for them.
  double busy_high = 0.8;
  double slack_low = 0.1;
  /// A frame is calm when, at the level above, its own CPU time would have taken less than this
  /// share of that level's period and its wall time less than `busy_high` of it, and the slack
  /// is above `slack_high`.
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

/// One frame's cost, ms: its wall time (skin, draw and JPEG, with any wait for the core) and
/// the render thread's own CPU time for it (render::FrameTimings::cpu_ms).
struct FrameCost {
  double wall_ms = 0.0;
  double cpu_ms = 0.0;
};

/// Level 0 is the configured stream; each next one costs less: the rate first, then the size.
inline constexpr std::array<FrameLevel, 6> kFrameLevels = {
    {{1.0, 1.0}, {0.6, 1.0}, {0.4, 1.0}, {0.4, 0.75}, {0.4, 0.5}, {0.2, 0.5}}};

class FrameGovernor {
 public:
  explicit FrameGovernor(FrameGovernorConfig config = {}) : config_(config) {}

  /// Takes one frame's cost at the current level's period `period_ms`, and the mechanics' step
  /// slack (1 - step wall time / step period; >= 1 when unknown). @return true when the level
  /// changed.
  bool Update(const FrameCost& cost, double period_ms, double step_slack);
  /// A frame whose wall time was all its own (nothing else ran on its core meanwhile).
  bool Update(double frame_ms, double period_ms, double step_slack) {
    return Update(FrameCost{frame_ms, frame_ms}, period_ms, step_slack);
  }

  int level() const { return level_; }
  const FrameLevel& current() const { return kFrameLevels[level_]; }

 private:
  FrameGovernorConfig config_;
  int level_ = 0;
  int overloaded_ = 0;
  int calm_ = 0;
};

}  // namespace viscera::server
