#include "render/mesh_renderer.h"

#include <gtest/gtest.h>

#include <numbers>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "render/camera.h"
#include "render/jpeg_encoder.h"
#include "render/offscreen_context.h"

namespace viscera::render {
namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 120;

// Pixel (column, row from the top) where a world point projects.
cv::Point Project(const CameraMatrices& camera, const Eigen::Vector3f& point) {
  const Eigen::Vector4f clip = camera.projection * camera.view * point.homogeneous();
  const float x = clip.x() / clip.w();
  const float y = clip.y() / clip.w();
  return {static_cast<int>((x + 1.0f) * 0.5f * kWidth),
          static_cast<int>((1.0f - y) * 0.5f * kHeight)};
}

// Mean BGR of the 5x5 block around `p` (smooths JPEG's block noise).
cv::Vec3d MeanAround(const cv::Mat& image, cv::Point p) {
  const cv::Scalar mean = cv::mean(image(cv::Rect(p.x - 2, p.y - 2, 5, 5)));
  return {mean[0], mean[1], mean[2]};
}

TEST(MeshRenderer, LitTriangleShowsWhereItProjectsAndClearColourElsewhere) {
  OffscreenContext context(kWidth, kHeight);
  MeshRenderer renderer;

  // a triangle in the plane z = 0, in the upper right of the view, facing the camera
  VerticesF positions(3, 3);
  positions << -0.2f, 0.1f, 0.0f,  //
      0.6f, 0.1f, 0.0f,            //
      0.2f, 0.7f, 0.0f;
  VerticesF normals(3, 3);
  normals.rowwise() = Eigen::RowVector3f(0.0f, 0.0f, 1.0f);
  TrianglesU triangles(1, 3);
  triangles << 0, 1, 2;
  CameraMatrices camera;
  camera.view = LookAt({0.0f, 0.0f, 2.0f}, Eigen::Vector3f::Zero(), Eigen::Vector3f::UnitY());
  camera.projection =
      Perspective(std::numbers::pi_v<float> / 3, float{kWidth} / kHeight, 0.1f, 10.0f);
  Material red;
  red.albedo = {0.9f, 0.1f, 0.1f};
  red.ambient = 0.2f;
  red.specular = 0.0f;  // a highlight would whiten the centre; this test checks albedo

  const Eigen::Vector3f clear(0.1f, 0.2f, 0.3f);
  renderer.Clear(clear);
  renderer.Draw(positions, normals, triangles, camera, red);
  JpegEncoder encoder(90);
  const std::vector<uint8_t>& jpeg = encoder.Encode(context.Frame());

  const cv::Mat image = cv::imdecode(jpeg, cv::IMREAD_COLOR);
  ASSERT_EQ(image.cols, kWidth);
  ASSERT_EQ(image.rows, kHeight);
  cv::Scalar mean;
  cv::Scalar stddev;
  cv::meanStdDev(image, mean, stddev);
  EXPECT_GT(stddev[2], 20.0) << "frame is uniform";

  // Inside: the triangle's centroid. Lambert with the light at the eye: the face is
  // seen almost head-on (cos > 0.97), so R ~ 255 * 0.9 * (0.2 + 0.8 * 0.97) ~ 224.
  const Eigen::Vector3f centroid = positions.colwise().mean().transpose();
  const cv::Point inside = Project(camera, centroid);
  ASSERT_LT(inside.y, kHeight / 2) << "triangle should project into the upper half";
  const cv::Vec3d in = MeanAround(image, inside);
  EXPECT_NEAR(in[2], 224.0, 15.0) << "red";
  EXPECT_NEAR(in[1], 25.0, 15.0) << "green";
  EXPECT_NEAR(in[0], 25.0, 15.0) << "blue";

  // Outside: the same pixel mirrored top-to-bottom (catches a flipped frame) and the
  // lower left corner show the clear colour.
  const cv::Vec3d expected_clear(255.0 * clear.z(), 255.0 * clear.y(), 255.0 * clear.x());
  for (const cv::Point p :
       {cv::Point(inside.x, kHeight - 1 - inside.y), cv::Point(10, kHeight - 10)}) {
    const cv::Vec3d out = MeanAround(image, p);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(out[c], expected_clear[c], 6.0) << "at " << p << " channel " << c;
  }
}

TEST(MeshRenderer, NearerTriangleHidesTheFartherOne) {
  OffscreenContext context(kWidth, kHeight);
  MeshRenderer renderer;
  CameraMatrices camera;
  camera.view = LookAt({0.0f, 0.0f, 2.0f}, Eigen::Vector3f::Zero(), Eigen::Vector3f::UnitY());
  camera.projection =
      Perspective(std::numbers::pi_v<float> / 3, float{kWidth} / kHeight, 0.1f, 10.0f);
  VerticesF near_tri(3, 3);
  near_tri << -0.5f, -0.5f, 0.5f, 0.5f, -0.5f, 0.5f, 0.0f, 0.5f, 0.5f;
  VerticesF far_tri = near_tri;
  far_tri.col(2).setConstant(-0.5f);
  VerticesF normals(3, 3);
  normals.rowwise() = Eigen::RowVector3f(0.0f, 0.0f, 1.0f);
  TrianglesU triangles(1, 3);
  triangles << 0, 1, 2;
  Material green;
  green.albedo = {0.1f, 0.9f, 0.1f};
  green.specular = 0.0f;
  Material blue;
  blue.albedo = {0.1f, 0.1f, 0.9f};
  blue.specular = 0.0f;

  renderer.Clear(Eigen::Vector3f::Zero());
  renderer.Draw(near_tri, normals, triangles, camera, green);  // nearer first: depth must reject
  renderer.Draw(far_tri, normals, triangles, camera, blue);
  const cv::Mat frame = context.Frame();
  const cv::Vec4b centre = frame.at<cv::Vec4b>(Project(camera, {0.0f, -0.1f, 0.5f}));
  EXPECT_GT(centre[1], 150);  // green wins
  EXPECT_LT(centre[0], 60);
}

}  // namespace
}  // namespace viscera::render
