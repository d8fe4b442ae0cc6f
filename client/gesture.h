#pragma once
/// Tool paths for `viscera drive`: time-stamped waypoints, linearly interpolated. The
/// built-in "clearing" gesture sweeps a tool across the default scene's intestine to move
/// it aside; scripts give the same thing as text.
#include <string>
#include <vector>

#include "common/types.h"

namespace viscera::client {

struct Waypoint {
  double t = 0.0;             ///< s from the start of the gesture
  Vec3 position = Vec3::Zero();  ///< tool tip target (m, world frame)
  double jaw = 1.0;           ///< 0 closed .. 1 open
};

/// The clearing gesture (6 s): from above the left of the coil (x = -0.25 m), down to
/// 2 cm over the floor, a slow sweep to x = +0.25 m through the intestine, and up again.
std::vector<Waypoint> ClearingGesture();

/// A script: one waypoint per line, "t x y z [jaw]" (s, m, m, m, 0..1), times increasing;
/// blank lines and lines starting with '#' are ignored.
/// @throws InputError naming the line when the file cannot be read or a line is bad.
std::vector<Waypoint> LoadScript(const std::string& path);

/// The target at time t (clamped to the path's span). @pre path not empty.
Waypoint Sample(const std::vector<Waypoint>& path, double t);

}  // namespace viscera::client
