#include "render/camera.h"

#include <cmath>
#include <numbers>

#include "common/check.h"

namespace viscera::render {

Eigen::Matrix4f LookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target,
                       const Eigen::Vector3f& up) {
  const Eigen::Vector3f forward_raw = target - eye;
  ThrowUnless(forward_raw.norm() > 1e-9f, "LookAt: eye and target coincide");
  const Eigen::Vector3f forward = forward_raw.normalized();
  const Eigen::Vector3f side_raw = forward.cross(up);
  ThrowUnless(side_raw.norm() > 1e-6f * up.norm() && up.norm() > 0.0f,
              "LookAt: up is zero or parallel to the viewing direction");
  const Eigen::Vector3f side = side_raw.normalized();
  const Eigen::Vector3f true_up = side.cross(forward);
  // Rows are the camera axes in world coordinates: x = side, y = up, z = -forward.
  Eigen::Matrix4f view = Eigen::Matrix4f::Identity();
  view.block<1, 3>(0, 0) = side.transpose();
  view.block<1, 3>(1, 0) = true_up.transpose();
  view.block<1, 3>(2, 0) = -forward.transpose();
  view(0, 3) = -side.dot(eye);
  view(1, 3) = -true_up.dot(eye);
  view(2, 3) = forward.dot(eye);
  return view;
}

Eigen::Matrix4f Perspective(float fovy, float aspect, float near, float far) {
  ThrowUnless(fovy > 0.0f && fovy < std::numbers::pi_v<float>, "Perspective: fovy ", fovy,
              " rad is outside (0, pi)");
  ThrowUnless(aspect > 0.0f, "Perspective: aspect ", aspect, " must be > 0");
  ThrowUnless(near > 0.0f && far > near, "Perspective: need 0 < near < far, got near ", near,
              " far ", far);
  const float f = 1.0f / std::tan(0.5f * fovy);
  Eigen::Matrix4f projection = Eigen::Matrix4f::Zero();
  projection(0, 0) = f / aspect;
  projection(1, 1) = f;
  projection(2, 2) = (far + near) / (near - far);
  projection(2, 3) = 2.0f * far * near / (near - far);
  projection(3, 2) = -1.0f;
  return projection;
}

}  // namespace viscera::render
