// Running the bowel's damage drawn on the bowel: a straight tube seen from above, the segments
// given as damaged drawn in the damage colour, where they lie along it and nowhere else (the
// decoded JPEG's columns, which map linearly to positions along a tube at one depth).
#include <gtest/gtest.h>

#include <algorithm>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "render/frame_renderer.h"

namespace viscera::render {
namespace {

constexpr double kLength = 0.3;  // m, along x, centred on the origin

mechanics::ModelParams Tube() {
  mechanics::ModelParams p;
  p.radius = 0.0125;
  p.length = kLength;
  p.initial_q.resize(31, 3);
  for (int i = 0; i <= 30; ++i) p.initial_q.row(i) << -0.5 * kLength + kLength * i / 30.0, 0, 0;
  return p;
}

struct Columns {
  int tube_first = -1, tube_last = -1;      // columns with any bowel
  int damage_first = -1, damage_last = -1;  // columns with the damage colour
  long damage_pixels = 0;
};

Columns Render(const std::vector<std::pair<double, double>>& damage) {
  const mechanics::ModelParams p = Tube();
  FrameOptions options;
  options.width = 320;
  options.height = 240;
  options.jpeg_quality = 95;
  FrameRenderer renderer(p, options);
  renderer.SetDamage(damage);
  Laparoscope scope;
  scope.eye = {0.0f, -0.02f, 0.3f};
  scope.target = {0.0f, 0.0f, 0.0f};
  scope.light_range = 0.6f;
  renderer.Render(p.initial_q, {}, scope);
  const cv::Mat image = cv::imdecode(renderer.Encode(), cv::IMREAD_COLOR);
  Columns c;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b bgr = image.at<cv::Vec3b>(y, x);
      const bool bowel = bgr[2] > 60 || bgr[0] > 60;  // the background is dark
      const bool hurt = bgr[0] > 140 && bgr[2] < 120 && bgr[1] < 90;
      if (bowel) {
        c.tube_first = c.tube_first < 0 ? x : std::min(c.tube_first, x);
        c.tube_last = std::max(c.tube_last, x);
      }
      if (hurt) {
        ++c.damage_pixels;
        c.damage_first = c.damage_first < 0 ? x : std::min(c.damage_first, x);
        c.damage_last = std::max(c.damage_last, x);
      }
    }
  }
  return c;
}

// Where a fraction f of the tube's length projects, as a fraction of the tube's columns (its
// ends are capped by half a radius beyond the centre line).
double Fraction(const Columns& c, int column) {
  return static_cast<double>(column - c.tube_first) / (c.tube_last - c.tube_first);
}

TEST(DamageColour, NoDamageNoDamageColour) {
  const Columns c = Render({});
  ASSERT_GT(c.tube_last - c.tube_first, 100);  // the tube spans the frame
  EXPECT_EQ(c.damage_pixels, 0);
}

TEST(DamageColour, TheDamagedSegmentsAreDrawnWhereTheyAreAndOnlyThere) {
  const Columns c = Render({{0.4, 0.6}});
  ASSERT_GT(c.damage_pixels, 200);
  // 40-60 % of the length: the middle fifth of the columns, within the caps' and a triangle's
  // share
  EXPECT_GT(Fraction(c, c.damage_first), 0.36);
  EXPECT_LT(Fraction(c, c.damage_first), 0.42);
  EXPECT_GT(Fraction(c, c.damage_last), 0.58);
  EXPECT_LT(Fraction(c, c.damage_last), 0.64);
}

TEST(DamageColour, AnEndSegmentIsDrawnAtItsEnd) {
  const Columns c = Render({{0.0, 0.1}});
  ASSERT_GT(c.damage_pixels, 100);
  const double first = Fraction(c, c.damage_first), last = Fraction(c, c.damage_last);
  // s = 0 lies at one end of the frame: the damage fills the first or the last tenth
  EXPECT_TRUE((first < 0.03 && last < 0.14) || (first > 0.86 && last > 0.97))
      << first << " .. " << last;
}

}  // namespace
}  // namespace viscera::render
