#include "render/laparoscope.h"

#include <gtest/gtest.h>

namespace viscera::render {
namespace {

TEST(Laparoscope, TargetProjectsToTheCentreInFront) {
  Laparoscope scope;
  scope.eye = {0.1f, -0.2f, 0.3f};
  scope.target = {0.0f, 0.05f, 0.1f};
  const CameraMatrices m = scope.Matrices(640, 480);
  const Projection p = Project(m, 640, 480, scope.target);
  EXPECT_NEAR(p.pixel.x(), 320.0f, 1e-3f);
  EXPECT_NEAR(p.pixel.y(), 240.0f, 1e-3f);
  EXPECT_NEAR(p.depth, (scope.eye - scope.target).norm(), 1e-5f);
  EXPECT_EQ(m.light_range, scope.light_range);
  // up in the world is up in the image (rows grow downward)
  EXPECT_LT(Project(m, 640, 480, scope.target + Eigen::Vector3f(0, 0, 0.01f)).pixel.y(), 240.0f);
}

TEST(Laparoscope, FramingSeesTheWholeBoxFromAboveAndInFront) {
  const Vec3 lo(-0.15, -0.1, 0.0), hi(0.12, 0.11, 0.1);
  for (const auto& [w, h] : {std::pair{640, 480}, {1280, 720}, {240, 320}}) {
    const Laparoscope scope = FramingLaparoscope(lo, hi, w, h);
    EXPECT_GT(scope.eye.z(), hi.z());
    EXPECT_LT(scope.eye.y(), lo.y());
    const CameraMatrices m = scope.Matrices(w, h);
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 c((corner & 1) ? hi.x() : lo.x(), (corner & 2) ? hi.y() : lo.y(),
                   (corner & 4) ? hi.z() : lo.z());
      const Projection p = Project(m, w, h, c.cast<float>());
      EXPECT_GT(p.depth, scope.near);
      EXPECT_GE(p.pixel.x(), 0.0f);
      EXPECT_LE(p.pixel.x(), static_cast<float>(w));
      EXPECT_GE(p.pixel.y(), 0.0f);
      EXPECT_LE(p.pixel.y(), static_cast<float>(h));
    }
  }
}

}  // namespace
}  // namespace viscera::render
