// The laparoscope's view in real OSMesa frames: the scope's spot light (inverse-square fall-off
// and its cone, measured on a flat wall), oblique optics (a marker on the shaft's axis moves
// where 30 degrees predict), and the target's patch against the textured peritoneum.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <opencv2/core.hpp>

#include "render/frame_renderer.h"
#include "render/port_scope.h"

namespace viscera::render {
namespace {

constexpr int kWidth = 640, kHeight = 480;
constexpr float kDegree = std::numbers::pi_v<float> / 180.0f;

// A short straight tube 1 m above everything the tests look at (behind their cameras).
mechanics::ModelParams Empty() {
  mechanics::ModelParams p;
  p.radius = 0.0125;
  p.length = 0.3;
  p.initial_q.resize(8, 3);
  for (int i = 0; i < 8; ++i) p.initial_q.row(i) << 0.04 * i - 0.14, 0.0, 1.0;
  return p;
}

Material Matte(const Eigen::Vector3f& albedo, float ambient) {
  Material m;
  m.albedo = albedo;
  m.ambient = ambient;
  m.specular = 0.0f;
  m.sheen = 0.0f;
  return m;
}

cv::Vec4b At(const cv::Mat& bgra, int col, int row) { return bgra.at<cv::Vec4b>(row, col); }

// The flat wall z = 0 in white, lit only by the scope (no ambient, no highlight), seen straight
// on from height D: a pixel whose ray leaves the axis at angle a shows, per channel,
// 255 cos(a) / (1 + (d / range)^2) spot(a), d = D / cos(a).
class SpotOnAWall : public ::testing::Test {
 protected:
  static constexpr float kRange = 0.1f, kInner = 20.0f, kOuter = 40.0f;

  cv::Mat Render(float height, bool cone) {
    mechanics::ModelParams p = Empty();
    collision::Obstacle wall;
    wall.kind = collision::ObstacleKind::kPlane;
    wall.name = "wall";
    p.obstacles = {wall};
    options_.width = kWidth;
    options_.height = kHeight;
    options_.palette.cavity_wall = Matte({1.0f, 1.0f, 1.0f}, 0.0f);
    renderer_.reset();  // one context at a time: the old one must go before the new one is made
    renderer_ = std::make_unique<FrameRenderer>(p, options_);
    scope_.eye = {0.0f, 0.0f, height};
    scope_.target = {0.0f, 0.0f, 0.0f};
    scope_.up = {0.0f, 1.0f, 0.0f};
    scope_.fov_y_degrees = 90.0f;
    scope_.light_range = kRange;
    scope_.spot_inner_deg = cone ? kInner : 0.0f;
    scope_.spot_outer_deg = cone ? kOuter : 0.0f;
    return renderer_->Render(p.initial_q, {}, scope_).clone();
  }

  // The predicted level of pixel (col, row) of a frame rendered from `height`.
  double Predicted(int col, int row, float height, bool cone) const {
    const double t = std::tan(0.5 * scope_.fov_y_degrees * kDegree);
    const double x = ((col + 0.5) / kWidth * 2.0 - 1.0) * t * kWidth / kHeight;
    const double y = (1.0 - (row + 0.5) / kHeight * 2.0) * t;
    const double cos_a = 1.0 / std::sqrt(1.0 + x * x + y * y);
    const double d = height / cos_a;
    double spot = 1.0;
    if (cone) {
      const double lo = std::cos(kOuter * kDegree), hi = std::cos(kInner * kDegree);
      const double u = std::clamp((cos_a - lo) / (hi - lo), 0.0, 1.0);
      spot = u * u * (3.0 - 2.0 * u);
    }
    return std::min(255.0, 255.0 * cos_a / (1.0 + (d / kRange) * (d / kRange)) * spot);
  }

  // The column of the centre row whose ray leaves the axis at `degrees`.
  int ColumnAt(double degrees) const {
    const double t = std::tan(0.5 * scope_.fov_y_degrees * kDegree);
    return static_cast<int>(0.5 * kWidth *
                            (1.0 + std::tan(degrees * kDegree) / (t * kWidth / kHeight)));
  }

  FrameOptions options_;
  std::unique_ptr<FrameRenderer> renderer_;
  Laparoscope scope_;
};

TEST_F(SpotOnAWall, TheLightFallsOffWithTheSquareOfTheDistance) {
  double previous = 256.0;
  for (const float height : {0.03f, 0.05f, 0.1f, 0.2f, 0.4f}) {
    const cv::Mat frame = Render(height, true);
    const int col = kWidth / 2, row = kHeight / 2;
    const double measured = At(frame, col, row)[2];
    EXPECT_NEAR(measured, Predicted(col, row, height, true), 2.0) << "at " << height << " m";
    EXPECT_LT(measured, previous) << "farther is darker";
    previous = measured;
  }
}

TEST_F(SpotOnAWall, ThePixelsFollowTheConeAndAreDarkOutsideIt) {
  constexpr float kHeightM = 0.1f;
  const cv::Mat frame = Render(kHeightM, true);
  for (const double degrees : {0.0, 10.0, 19.0, 25.0, 30.0, 35.0, 39.0, 45.0, 50.0}) {
    const int col = ColumnAt(degrees), row = kHeight / 2;
    const cv::Vec4b px = At(frame, col, row);
    EXPECT_NEAR(px[2], Predicted(col, row, kHeightM, true), 2.0)
        << degrees << " degrees off the axis";
    EXPECT_EQ(px[0], px[2]) << "a white wall stays grey";
  }
  EXPECT_LE(At(frame, ColumnAt(45.0), kHeight / 2)[2], 1) << "no light beyond the cone";
  EXPECT_GT(At(frame, ColumnAt(30.0), kHeight / 2)[2], 10) << "the cone's edge is soft";
  // control: without the cone the same pixel beyond it is lit as the fall-off alone says
  const cv::Mat plain = Render(kHeightM, false);
  const int col = ColumnAt(45.0);
  EXPECT_GT(At(plain, col, kHeight / 2)[2], 40);
  EXPECT_NEAR(At(plain, col, kHeight / 2)[2], Predicted(col, kHeight / 2, kHeightM, false), 2.0);
}

// Oblique optics: a scope through a port at (0, 0, 0.3) aimed straight down, a small green
// marker on the shaft's axis 15 cm below the tip. Forward optics show it at the centre; 30
// degree optics look 30 degrees off the shaft, so it moves by f tan(30) pixels (f = 240 /
// tan(35 degrees)) to the side opposite to where they look.
class ObliqueOptics : public ::testing::Test {
 protected:
  // The centroid (col, row) of the marker's pixels, and how many there are.
  Eigen::Vector2d Marker(double optics, double roll, int* count) {
    mechanics::ModelParams p = Empty();
    collision::Obstacle marker;
    marker.kind = collision::ObstacleKind::kSphere;
    marker.name = "marker";
    marker.centre = {0.0, 0.0, 0.10};
    marker.radius = 0.003;
    p.obstacles = {marker};
    mechanics::ScopeParams s;
    s.port = {0.0, 0.0, 0.3};
    s.look_at = {0.0, 0.0, 0.0};
    s.insertion = 0.05;
    s.up = {0.0, 1.0, 0.0};
    s.optics_deg = optics;
    s.roll_deg = roll;
    FrameOptions options;
    options.palette.named_organs.clear();
    options.palette.organs = {Matte({0.1f, 1.0f, 0.1f}, 1.0f)};
    FrameRenderer renderer(p, options);
    const cv::Mat frame = renderer.Render(p.initial_q, {}, PortLaparoscope(s));
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    *count = 0;
    for (int r = 0; r < frame.rows; ++r) {
      for (int c = 0; c < frame.cols; ++c) {
        const cv::Vec4b px = At(frame, c, r);
        if (px[1] > 128 && px[1] > px[2] + 60) {
          sum += Eigen::Vector2d(c + 0.5, r + 0.5);
          ++*count;
        }
      }
    }
    return *count > 0 ? Eigen::Vector2d(sum / *count) : sum;
  }
};

TEST_F(ObliqueOptics, AMarkerOnTheShaftMovesAsThirtyDegreesPredict) {
  const double shift =
      0.5 * kHeight / std::tan(35.0 * kDegree) * std::tan(30.0 * kDegree);  // 198 px
  const Eigen::Vector2d centre(0.5 * kWidth, 0.5 * kHeight);
  struct Case {
    double optics, roll;
    Eigen::Vector2d expected;
  };
  for (const Case& c :
       {Case{0.0, 0.0, centre}, Case{30.0, 0.0, centre + Eigen::Vector2d(0.0, -shift)},
        Case{30.0, 90.0, centre + Eigen::Vector2d(-shift, 0.0)},
        Case{30.0, 180.0, centre + Eigen::Vector2d(0.0, shift)}}) {
    int count = 0;
    const Eigen::Vector2d at = Marker(c.optics, c.roll, &count);
    EXPECT_GT(count, 50) << "optics " << c.optics << ", roll " << c.roll;
    EXPECT_NEAR(at.x(), c.expected.x(), 1.5) << "optics " << c.optics << ", roll " << c.roll;
    EXPECT_NEAR(at.y(), c.expected.y(), 1.5) << "optics " << c.optics << ", roll " << c.roll;
  }
}

TEST(PortLaparoscope, TheTipIsOnTheShaftAndTheLightIsASpot) {
  mechanics::ScopeParams s;
  s.port = {0.1, -0.1, 0.3};
  s.look_at = {0.0, 0.0, 0.1};
  s.insertion = 0.06;
  const Laparoscope l = PortLaparoscope(s);
  const Vec3 shaft = (s.look_at - s.port).normalized();
  EXPECT_LT((l.eye.cast<double>() - (s.port + 0.06 * shaft)).norm(), 1e-6);
  EXPECT_GT((l.target - l.eye).cast<double>().normalized().dot(shaft), 1.0 - 1e-6)
      << "forward optics";
  EXPECT_FLOAT_EQ(l.spot_outer_deg, static_cast<float>(s.light_cone_deg));
  EXPECT_FLOAT_EQ(l.spot_inner_deg, kSpotInnerFraction * l.spot_outer_deg);
  s.optics_deg = 30.0;
  const Laparoscope oblique = PortLaparoscope(s);
  EXPECT_NEAR((oblique.target - oblique.eye).cast<double>().normalized().dot(shaft),
              std::cos(30.0 * kDegree), 1e-6);
}

// The target's patch on the textured peritoneum, seen through the default scope: every pixel of
// the patch is far in colour from every pixel of the wall around it.
TEST(TargetPatch, StandsOutFromTheTexturedWall) {
  mechanics::ModelParams p = Empty();
  collision::Obstacle cavity;
  cavity.kind = collision::ObstacleKind::kEllipsoid;
  cavity.name = "cavity";
  cavity.centre = {0.0, 0.0, 0.13};
  cavity.radii = {0.20, 0.16, 0.13};
  cavity.inside = true;
  p.obstacles = {cavity};
  mechanics::TargetParams lesion;
  lesion.name = "lesion";
  lesion.centre = {0.0, 0.0, 0.003};
  lesion.normal = Vec3::UnitZ();
  lesion.radius = 0.008;
  p.task.targets = {lesion};
  mechanics::ScopeParams s;
  s.port = {0.0, -0.1, 0.28};
  s.look_at = {0.0, 0.0, 0.0};
  FrameRenderer renderer(p, FrameOptions{});
  const Laparoscope scope = PortLaparoscope(s);
  const cv::Mat frame = renderer.Render(p.initial_q, {}, scope).clone();
  const CameraMatrices m = scope.Matrices(kWidth, kHeight);
  auto pixel = [&](const Vec3& world) {
    const Eigen::Vector2f at = Project(m, kWidth, kHeight, world.cast<float>()).pixel;
    const cv::Vec4b px = At(frame, static_cast<int>(at.x()), static_cast<int>(at.y()));
    return Eigen::Vector3d(px[2], px[1], px[0]);
  };
  std::vector<Eigen::Vector3d> patch, wall;
  for (int k = 0; k < 48; ++k) {
    const double a = 2.0 * std::numbers::pi * k / 48.0;
    const Vec3 dir(std::cos(a), std::sin(a), 0.0);
    for (const double r : {0.0, 0.3, 0.6})
      patch.push_back(pixel(lesion.centre + r * lesion.radius * dir));
    for (const double r : {1.6, 2.5, 4.0}) {
      // on the cavity's floor: z where the ellipsoid passes under (x, y)
      const Vec3 xy = r * lesion.radius * dir;
      const double z =
          0.13 - 0.13 * std::sqrt(1.0 - std::pow(xy.x() / 0.2, 2) - std::pow(xy.y() / 0.16, 2));
      wall.push_back(pixel(Vec3(xy.x(), xy.y(), z)));
    }
  }
  double closest = 1e9;
  for (const Eigen::Vector3d& t : patch) {
    for (const Eigen::Vector3d& w : wall) closest = std::min(closest, (t - w).norm());
  }
  EXPECT_GT(closest, 120.0) << "RGB levels between the patch and the wall";
  // the wall around it is textured: its pixels are not all one colour
  double spread = 0.0;
  for (const Eigen::Vector3d& w : wall) spread = std::max(spread, (w - wall.front()).norm());
  EXPECT_GT(spread, 15.0);
}

// A scene without [camera] keeps its plain framing camera; one with it gets its scope.
TEST(SceneLaparoscope, TheScenesScopeElseTheFraming) {
  mechanics::ModelParams p = Empty();
  const Points& q = p.initial_q;
  const Laparoscope framing = SceneLaparoscope(p, q, kWidth, kHeight);
  const Laparoscope expected = FramingLaparoscope(
      q.colwise().minCoeff().transpose(), q.colwise().maxCoeff().transpose(), kWidth, kHeight);
  EXPECT_EQ(framing.eye, expected.eye);
  EXPECT_EQ(framing.spot_outer_deg, 0.0f);
  p.scope = mechanics::ScopeParams{};
  p.scope->port = {0.0, -0.1, 0.3};
  p.scope->look_at = {0.0, 0.0, 0.0};
  EXPECT_EQ(SceneLaparoscope(p, q, kWidth, kHeight).eye, PortLaparoscope(*p.scope).eye);
}

}  // namespace
}  // namespace viscera::render
