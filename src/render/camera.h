#pragma once
/// Camera matrices (OpenGL conventions: right-handed view space, the camera looks
/// down -z; clip space z in [-1, 1]).
#include <Eigen/Dense>

namespace viscera::render {

/// World-to-view transform of a camera at `eye` (m, world) looking at `target` (m,
/// world) with `up` roughly up.
/// @throws InputError when eye == target or up is parallel to the viewing direction.
Eigen::Matrix4f LookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target,
                       const Eigen::Vector3f& up);

/// Perspective projection: vertical field of view `fovy` (rad, in (0, pi)), `aspect`
/// = width / height, clip planes 0 < near < far (m).
/// @throws InputError for values outside those ranges.
Eigen::Matrix4f Perspective(float fovy, float aspect, float near, float far);

}  // namespace viscera::render
