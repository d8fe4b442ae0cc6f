#pragma once
/// Starting poses of the intestine ([intestine.shape]). Every shape places its control points at
/// equal arc-length spacing length / (N - 1), so the tube starts unstretched whatever N is.
#include <vector>

#include "collision/obstacle.h"
#include "common/types.h"
#include "scene/toml_reader.h"

namespace viscera::scene {

/// Reads the shape table (consuming its keys) and returns #N by 3 control points.
/// `num_points` may be 0 for kind = "points" (the list decides).
/// @throws InputError naming the offending key.
Points MakeShape(const TomlReader& shape, int num_points, double length);

/// Where a starting pose lies deepest inside an obstacle: the control point whose centre is
/// farthest on the wrong side of an obstacle's surface (outside a cavity, inside an organ).
struct StartOverlap {
  int point = -1;       ///< the control point; -1 when every one is in free space
  size_t obstacle = 0;  ///< index into the obstacles
  double depth = 0.0;   ///< how far its centre is past the surface (m, > 0)
};
StartOverlap DeepestStartOverlap(const Points& q,
                                 const std::vector<collision::Obstacle>& obstacles);

/// Refuses a starting pose `q` of a tube of `radius` whose centre line lies more than the radius
/// past an obstacle's surface: there the whole tube is inside the obstacle, with nothing of it in
/// free space, and the contacts would throw it out over its first steps (scenes/bowel_run.toml's
/// first coil, 7 cm outside its cavity, took seconds of CPU a step and 32 sub-steps). A tube that
/// starts in contact, partly in an obstacle, is pushed out and accepted.
/// @throws InputError naming the obstacle, the control point, its s and the depth.
void CheckStartClear(const Points& q, double radius,
                     const std::vector<collision::Obstacle>& obstacles);

}  // namespace viscera::scene
