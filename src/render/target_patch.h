#pragma once
/// The training task's targets drawn as flat patches (a disc or a polygon), lifted a little
/// off their plane toward `normal` so the wall they lie on never hides them by depth-fighting.
#include "mechanics/task_params.h"
#include "render/gpu_mesh.h"

namespace viscera::render {

/// Lift off the target's plane (m): more than the sag of the cavity wall's tessellation.
inline constexpr double kTargetLift = 0.0005;

/// Appends the patch of `target` (a fan of triangles, both sides share the normal).
void AppendTargetPatch(const mechanics::TargetParams& target, TriMesh* out);

}  // namespace viscera::render
