#pragma once
/// Sample points of a target patch: the exposure is the fraction of them the laparoscope sees.
#include <vector>

#include "common/types.h"
#include "mechanics/task_params.h"

namespace viscera::assessment {

/// About `target.samples` points spread evenly over the patch (m, world): a disc by Vogel's
/// sunflower spiral (equal area per point, centre to rim), a polygon by a square grid clipped
/// to it (at least its centre). Deterministic.
/// @pre target is valid (scene reader): radius > 0 or >= 3 coplanar corners, unit normal.
std::vector<Vec3> TargetSamples(const mechanics::TargetParams& target);

/// The polygon's corners' plane normal (Newell's method, unit; zero when degenerate) and its
/// area (m^2).
Vec3 PolygonNormal(const std::vector<Vec3>& corners);
double PolygonArea(const std::vector<Vec3>& corners);

}  // namespace viscera::assessment
