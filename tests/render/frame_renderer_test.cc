// Renders known scenes and checks the decoded JPEG where the geometry projects.
#include "render/frame_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/check.h"

namespace viscera::render {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;
constexpr double kRadius = 0.0125;

// A U-shaped skeleton in the plane z = 0: two 0.16 m arms along y, 0.12 m apart, joined by a
// half circle, 40 control points.
Points USkeleton() {
  std::vector<Vec3> points;
  for (int i = 0; i < 12; ++i) points.emplace_back(-0.06, 0.08 - 0.16 * i / 12.0, 0.0);
  for (int i = 0; i < 16; ++i) {
    const double a = std::numbers::pi * (1.0 - i / 16.0);
    points.emplace_back(0.06 * std::cos(a), -0.08 - 0.06 * std::sin(a), 0.0);
  }
  for (int i = 0; i <= 12; ++i) points.emplace_back(0.06, -0.08 + 0.16 * i / 12.0, 0.0);
  Points q(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t i = 0; i < points.size(); ++i)
    q.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  return q;
}

mechanics::ModelParams Scene() {
  mechanics::ModelParams p;
  p.radius = kRadius;
  p.initial_q = USkeleton();
  return p;
}

Laparoscope Scope() {
  Laparoscope scope;
  scope.eye = {0.0f, -0.2f, 0.25f};
  scope.target = {0.0f, 0.0f, 0.0f};
  scope.light_range = 0.5f;
  return scope;
}

// The tests' frame size, every other option at its default.
FrameOptions FullSize() {
  FrameOptions options;
  options.width = kWidth;
  options.height = kHeight;
  return options;
}

cv::Mat Decode(const std::vector<uint8_t>& jpeg) { return cv::imdecode(jpeg, cv::IMREAD_COLOR); }

// Mean BGR over the 3x3 block around a continuous pixel position.
cv::Vec3d MeanAround(const cv::Mat& image, const Eigen::Vector2f& pixel) {
  const int x = static_cast<int>(pixel.x()), y = static_cast<int>(pixel.y());
  const cv::Scalar m = cv::mean(image(cv::Rect(x - 1, y - 1, 3, 3)));
  return {m[0], m[1], m[2]};
}

// Pink: red clearly above green and blue, lit (the wet highlight may whiten it a little).
bool IntestineColoured(const cv::Vec3d& bgr) {
  return bgr[2] > 110.0 && bgr[2] > bgr[1] + 25.0 && bgr[2] > bgr[0] + 25.0;
}

bool Background(const cv::Vec3d& bgr, const Palette& palette) {
  for (int c = 0; c < 3; ++c) {
    if (std::abs(bgr[c] - 255.0 * palette.background[2 - c]) > 8.0) return false;
  }
  return true;
}

TEST(FrameRenderer, IntestineWhereTheSkeletonProjectsBackgroundElsewhere) {
  const mechanics::ModelParams scene = Scene();
  for (const char* skin : {"parametric", "convolution", "implicit", "hybrid"}) {
    SCOPED_TRACE(skin);
    FrameOptions options = FullSize();
    options.skin = skin;
    FrameRenderer renderer(scene, options);
    const Laparoscope scope = Scope();
    renderer.Render(scene.initial_q, {}, scope);
    const cv::Mat image = Decode(renderer.Encode());
    ASSERT_EQ(image.cols, kWidth);
    ASSERT_EQ(image.rows, kHeight);
    cv::Scalar mean, stddev;
    cv::meanStdDev(image, mean, stddev);
    EXPECT_GT(stddev[2], 20.0) << "uniform frame";

    const CameraMatrices m = scope.Matrices(kWidth, kHeight);
    // control points of both arms and the bend (not the rounded ends)
    for (int i : {3, 8, 14, 20, 26, 32, 37}) {
      const Projection p =
          Project(m, kWidth, kHeight, scene.initial_q.row(i).transpose().cast<float>());
      const cv::Vec3d bgr = MeanAround(image, p.pixel);
      EXPECT_TRUE(IntestineColoured(bgr))
          << "control point " << i << " at " << p.pixel.transpose() << ": BGR " << bgr;
    }
    // between the arms, beyond the ends, and the corners: nothing there
    for (const Eigen::Vector3f& empty :
         {Eigen::Vector3f(0.0f, 0.0f, 0.0f), Eigen::Vector3f(0.0f, 0.13f, 0.0f),
          Eigen::Vector3f(0.13f, -0.05f, 0.0f), Eigen::Vector3f(-0.13f, 0.0f, 0.0f)}) {
      const Projection p = Project(m, kWidth, kHeight, empty);
      ASSERT_GT(p.pixel.x(), 2.0f);
      ASSERT_LT(p.pixel.x(), kWidth - 2.0f);
      EXPECT_TRUE(Background(MeanAround(image, p.pixel), renderer.scene().palette()))
          << "at " << empty.transpose() << ": BGR " << MeanAround(image, p.pixel);
    }
    for (const Eigen::Vector2f& corner :
         {Eigen::Vector2f(3, 3), Eigen::Vector2f(kWidth - 4, kHeight - 4)}) {
      EXPECT_TRUE(Background(MeanAround(image, corner), renderer.scene().palette()));
    }
  }
}

TEST(FrameRenderer, TimesTheFramesCpuApartFromItsWallTime) {
  // LP_NUM_THREADS=0: the whole frame is drawn on this thread, so its CPU time is positive and
  // within its wall time (the frame governor tells a busy core from a costly frame by the two)
  const mechanics::ModelParams scene = Scene();
  FrameOptions options = FullSize();
  FrameRenderer renderer(scene, options);
  renderer.Render(scene.initial_q, {}, Scope());
  const double drawn_cpu_ms = renderer.timings().cpu_ms;
  renderer.Encode();
  const FrameTimings& t = renderer.timings();
  EXPECT_GT(drawn_cpu_ms, 0.0);
  EXPECT_GT(t.cpu_ms, drawn_cpu_ms);  // the JPEG's CPU added
  EXPECT_LE(t.cpu_ms, t.skin_ms + t.render_ms + t.encode_ms + 0.1);
}

// A stream made smaller (the frame governor's SetFrameSize) draws the picture a renderer of that
// size draws, and back at full size the picture it drew before.
TEST(FrameRenderer, ASmallerFrameSizeDrawsThePictureOfThatSize) {
  const mechanics::ModelParams scene = Scene();
  FrameOptions options = FullSize();
  FrameRenderer renderer(scene, options);
  renderer.Render(scene.initial_q, {}, Scope());
  const cv::Mat full = Decode(renderer.Encode());
  renderer.SetFrameSize(kWidth / 2, kHeight / 2);
  renderer.Render(scene.initial_q, {}, Scope());
  const cv::Mat half = Decode(renderer.Encode());
  options.width = kWidth / 2;
  options.height = kHeight / 2;
  FrameRenderer small(scene, options);
  small.Render(scene.initial_q, {}, Scope());
  const cv::Mat reference = Decode(small.Encode());
  ASSERT_EQ(half.size(), reference.size());
  EXPECT_EQ(cv::norm(half, reference, cv::NORM_L1), 0.0);
  renderer.SetFrameSize(kWidth, kHeight);
  renderer.Render(scene.initial_q, {}, Scope());
  EXPECT_EQ(cv::norm(Decode(renderer.Encode()), full, cv::NORM_L1), 0.0);
  EXPECT_THROW(renderer.SetFrameSize(kWidth + 2, kHeight), InputError);
}

TEST(FrameRenderer, MovingTheCameraChangesTheImage) {
  const mechanics::ModelParams scene = Scene();
  FrameOptions options = FullSize();
  FrameRenderer renderer(scene, options);
  Laparoscope scope = Scope();
  renderer.Render(scene.initial_q, {}, scope);
  const cv::Mat first = Decode(renderer.Encode());
  renderer.Render(scene.initial_q, {}, scope);
  const cv::Mat same = Decode(renderer.Encode());
  EXPECT_EQ(cv::norm(first, same, cv::NORM_L1), 0.0) << "rendering is deterministic";
  scope.eye += Eigen::Vector3f(0.05f, 0.0f, 0.0f);
  renderer.Render(scene.initial_q, {}, scope);
  const cv::Mat moved = Decode(renderer.Encode());
  cv::Mat diff;
  cv::absdiff(first, moved, diff);
  cv::Mat grey;
  cv::cvtColor(diff, grey, cv::COLOR_BGR2GRAY);
  const double changed = cv::countNonZero(grey > 30) / static_cast<double>(kWidth * kHeight);
  EXPECT_GT(changed, 0.02) << "a 5 cm move of the scope must move the image";
}

// The cavity's inner wall, an organ and a tool each show in their own colours.
TEST(FrameRenderer, CavityWallOrganAndToolShowInTheirColours) {
  mechanics::ModelParams scene = Scene();
  collision::Obstacle cavity;
  cavity.kind = collision::ObstacleKind::kEllipsoid;
  cavity.name = "cavity";
  cavity.centre = {0.0, 0.0, 0.05};
  cavity.radii = {0.4, 0.4, 0.3};
  cavity.inside = true;
  collision::Obstacle liver;
  liver.kind = collision::ObstacleKind::kSphere;
  liver.name = "liver";
  liver.centre = {0.0, 0.0, 0.0};
  liver.radius = 0.03;
  scene.obstacles = {cavity, liver};
  mechanics::ToolParams tool;
  tool.name = "left";
  tool.port = {-0.1, -0.15, 0.3};
  scene.tools = {tool};
  std::vector<mechanics::ToolState> tools(1);
  tools[0].initialized = true;
  tools[0].tip = {-0.03, -0.12, 0.05};
  tools[0].jaw = 0.5;

  FrameOptions options = FullSize();
  for (const bool outside : {false, true}) {
    SCOPED_TRACE(outside ? "scope outside the cavity" : "scope inside the cavity");
    FrameRenderer renderer(scene, options);
    Laparoscope scope = Scope();
    if (outside) {  // 0.96 m away, beyond the wall: it sees through its near side
      scope.eye *= 3.0f;
      scope.light_range *= 3.0f;
    }
    cv::Mat rendered;
    cv::cvtColor(renderer.Render(scene.initial_q, tools, scope), rendered, cv::COLOR_BGRA2BGR);
    const cv::Mat image = Decode(renderer.Encode());
    const CameraMatrices m = scope.Matrices(kWidth, kHeight);
    // the liver: off its highlight, half a radius left of its centre as seen. In the rendered
    // pixels: from outside it is 5 px in radius, and JPEG's 4:2:0 chroma (colour at half
    // resolution) carries the pale peritoneum around it several pixels into it (+9 levels of green)
    const Eigen::Vector3f left = m.view.block<1, 3>(0, 0).transpose();
    const cv::Vec3d organ = MeanAround(rendered, Project(m, kWidth, kHeight, -0.015f * left).pixel);
    EXPECT_GT(organ[2], organ[1] + 40.0) << "liver BGR " << organ;
    EXPECT_LT(organ[1], 0.45 * organ[2]) << "liver is darker red than the intestine: BGR " << organ;
    // the tool shaft halfway between tip and port: grey, lit
    const Vec3 shaft = 0.5 * (tools[0].tip + tool.port);
    const cv::Vec3d grey =
        MeanAround(image, Project(m, kWidth, kHeight, shaft.cast<float>()).pixel);
    if (!outside) {
      EXPECT_GT(grey[0], 60.0) << "tool BGR " << grey;
      EXPECT_LT(std::abs(grey[2] - grey[0]), 35.0) << "tool BGR " << grey;
    }
    // seen from inside, the wall fills what used to be background
    const cv::Vec3d corner = MeanAround(image, Eigen::Vector2f(3, 3));
    if (!outside) {
      EXPECT_FALSE(Background(corner, renderer.scene().palette())) << "corner BGR " << corner;
      EXPECT_GT(corner[2], corner[0] + 5.0) << "the wall is reddish: BGR " << corner;
    }
    // the intestine still shows
    const Projection p =
        Project(m, kWidth, kHeight, scene.initial_q.row(3).transpose().cast<float>());
    EXPECT_TRUE(IntestineColoured(MeanAround(image, p.pixel))) << MeanAround(image, p.pixel);
  }
}

TEST(FrameRenderer, BadInputThrows) {
  const mechanics::ModelParams scene = Scene();
  FrameOptions options;
  options.width = 64;
  options.height = 48;
  options.skin = "marble";
  EXPECT_THROW(FrameRenderer(scene, options), InputError);
  options.skin = "parametric";
  FrameRenderer renderer(scene, options);
  Points short_q = scene.initial_q.topRows(10);
  EXPECT_THROW(renderer.Render(short_q, {}, Scope()), InputError);
  std::vector<mechanics::ToolState> tools(2);
  EXPECT_THROW(renderer.Render(scene.initial_q, tools, Scope()), InputError);
  int w = 0, h = 0;
  ParseFrameSize("1280x720", &w, &h);
  EXPECT_EQ(w, 1280);
  EXPECT_EQ(h, 720);
  for (const char* bad : {"1280", "1280x", "x720", "1280x720x3", "-5x4", "0x10", "12 x 4"}) {
    EXPECT_THROW(ParseFrameSize(bad, &w, &h), InputError) << bad;
  }
}

}  // namespace
}  // namespace viscera::render
