#include "render/camera.h"

#include <gtest/gtest.h>

#include <numbers>

#include "common/check.h"

namespace viscera::render {
namespace {

TEST(Camera, LookAtPutsTheTargetOnTheNegativeZAxis) {
  const Eigen::Vector3f eye(1.0f, 2.0f, 3.0f);
  const Eigen::Vector3f target(-1.0f, 0.5f, 0.0f);
  const Eigen::Matrix4f view = LookAt(eye, target, Eigen::Vector3f::UnitZ());
  const Eigen::Vector4f t = view * target.homogeneous();
  EXPECT_NEAR(t.x(), 0.0f, 1e-5f);
  EXPECT_NEAR(t.y(), 0.0f, 1e-5f);
  EXPECT_NEAR(t.z(), -(target - eye).norm(), 1e-5f);
  const Eigen::Vector4f e = view * eye.homogeneous();
  EXPECT_NEAR(e.head<3>().norm(), 0.0f, 1e-5f);
  // rigid: the rotation block is orthonormal
  const Eigen::Matrix3f r = view.block<3, 3>(0, 0);
  EXPECT_TRUE((r * r.transpose()).isIdentity(1e-5f));
  EXPECT_THROW(LookAt(eye, eye, Eigen::Vector3f::UnitZ()), InputError);
  EXPECT_THROW(LookAt(Eigen::Vector3f::Zero(), Eigen::Vector3f::UnitZ(), Eigen::Vector3f::UnitZ()),
               InputError);
}

TEST(Camera, PerspectiveMapsNearAndFarToTheClipRange) {
  const float near = 0.1f;
  const float far = 10.0f;
  const Eigen::Matrix4f p = Perspective(std::numbers::pi_v<float> / 2, 2.0f, near, far);
  const Eigen::Vector4f n = p * Eigen::Vector4f(0.0f, 0.0f, -near, 1.0f);
  const Eigen::Vector4f f = p * Eigen::Vector4f(0.0f, 0.0f, -far, 1.0f);
  EXPECT_NEAR(n.z() / n.w(), -1.0f, 1e-5f);
  EXPECT_NEAR(f.z() / f.w(), 1.0f, 1e-4f);
  // 90 degrees vertical: a point at 45 degrees up lands on the top edge
  const Eigen::Vector4f top = p * Eigen::Vector4f(0.0f, 1.0f, -1.0f, 1.0f);
  EXPECT_NEAR(top.y() / top.w(), 1.0f, 1e-5f);
  EXPECT_THROW(Perspective(0.0f, 1.0f, near, far), InputError);
  EXPECT_THROW(Perspective(1.0f, 1.0f, far, near), InputError);
}

}  // namespace
}  // namespace viscera::render
