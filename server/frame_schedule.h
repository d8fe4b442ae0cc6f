#pragma once
/// The render thread's schedule: frames on an absolute grid of ticks; a frame a little late
/// goes out at once, and the ticks that passed entirely while a frame was made are dropped.
#include <cstdint>

namespace viscera::server {

/// Slowest frame rate a session may ask for (Hz): keeps periods and tick arithmetic in range.
inline constexpr double kMinFrameRateHz = 1.0;

/// Advances `*next` (the tick just served, ns) past it to the next tick to serve, given the
/// time `now` (ns) and `period` (ns, > 0): the following tick, or, when `now` is at least a
/// whole period past that, the latest tick not after `now` (the ones before it are dropped).
/// @return the ticks dropped.
inline int64_t AdvanceFrameSchedule(int64_t* next, int64_t now, int64_t period) {
  *next += period;
  if (now < *next + period) return 0;
  const int64_t behind = (now - *next) / period;
  *next += behind * period;
  return behind;
}

}  // namespace viscera::server
