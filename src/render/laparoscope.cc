#include "render/laparoscope.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "render/camera.h"

namespace viscera::render {

CameraMatrices Laparoscope::Matrices(int width, int height) const {
  CameraMatrices m;
  m.view = LookAt(eye, target, up);
  m.projection = Perspective(fov_y_degrees * std::numbers::pi_v<float> / 180.0f,
                             static_cast<float>(width) / static_cast<float>(height), near, far);
  m.light_range = light_range;
  m.spot_inner_deg = spot_inner_deg;
  m.spot_outer_deg = spot_outer_deg;
  return m;
}

Projection Project(const CameraMatrices& camera, int width, int height,
                   const Eigen::Vector3f& point) {
  const Eigen::Vector4f view = camera.view * point.homogeneous();
  const Eigen::Vector4f clip = camera.projection * view;
  Projection p;
  p.depth = -view.z();
  p.pixel = {(clip.x() / clip.w() + 1.0f) * 0.5f * static_cast<float>(width),
             (1.0f - clip.y() / clip.w()) * 0.5f * static_cast<float>(height)};
  return p;
}

Laparoscope LookAtLaparoscope(const Vec3& eye, const Vec3& target, const Vec3& up,
                              double fov_y_degrees) {
  Laparoscope scope;
  scope.eye = eye.cast<float>();
  scope.target = target.cast<float>();
  scope.up = up.cast<float>();
  scope.fov_y_degrees = static_cast<float>(fov_y_degrees);
  scope.light_range = static_cast<float>(1.5 * (eye - target).norm());
  return scope;
}

Laparoscope FramingLaparoscope(const Vec3& lo, const Vec3& hi, int width, int height) {
  Laparoscope scope;
  const Vec3 centre = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * (hi - lo).norm(), 1e-3);
  // the half angle of the narrower side of the frame
  const double half_fov_y = 0.5 * scope.fov_y_degrees * std::numbers::pi / 180.0;
  const double aspect = static_cast<double>(width) / height;
  const double half_fov = std::min(half_fov_y, std::atan(aspect * std::tan(half_fov_y)));
  const double distance = radius / std::sin(half_fov);
  // from the front (-y) and above (+z), 50 degrees above the horizontal
  const double elevation = 50.0 * std::numbers::pi / 180.0;
  const Vec3 from(0.0, -std::cos(elevation), std::sin(elevation));
  scope.target = centre.cast<float>();
  scope.eye = (centre + distance * from).cast<float>();
  scope.up = Eigen::Vector3f::UnitZ();
  scope.near = static_cast<float>(std::max(1e-3, 0.01 * distance));
  scope.far = static_cast<float>(distance + 20.0 * radius + 1.0);
  scope.light_range = static_cast<float>(1.5 * distance);
  return scope;
}

}  // namespace viscera::render
