#pragma once
/// Starting poses of the intestine ([intestine.shape]). Every shape places its control points at
/// equal arc-length spacing length / (N - 1), so the tube starts unstretched whatever N is.
#include "common/types.h"
#include "scene/toml_reader.h"

namespace viscera::scene {

/// Reads the shape table (consuming its keys) and returns #N by 3 control points.
/// `num_points` may be 0 for kind = "points" (the list decides).
/// @throws InputError naming the offending key.
Points MakeShape(const TomlReader& shape, int num_points, double length);

}  // namespace viscera::scene
