// The procedural tissue textures in real OSMesa frames: the same scene draws the same pixels
// every time, the serosa's pattern is there, and it rides on the bowel (a rigid shift of tube
// and scope together leaves the picture alone), which a pattern fixed in the world would not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <opencv2/core.hpp>

#include "render/laparoscope.h"
#include "render/offscreen_context.h"
#include "render/scene_renderer.h"
#include "skin/skin.h"

namespace viscera::render {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr double kRadius = 0.0125;

constexpr int kPoints = 60;

// A wavy loop in the plane z = 0, shifted by `offset`.
Points Loop(const Vec3& offset) {
  Points q(kPoints, 3);
  for (int i = 0; i < kPoints; ++i) {
    const double a = 1.6 * std::numbers::pi * i / (kPoints - 1);
    q.row(i) = (Vec3(0.07 * std::cos(a), 0.07 * std::sin(a), 0.01 * std::sin(3.0 * a)) + offset)
                   .transpose();
  }
  return q;
}

class TissueTexture : public ::testing::Test {
 protected:
  // One frame of the loop shifted by `offset`, seen from a scope shifted the same way.
  cv::Mat Frame(const Vec3& offset, bool textures, bool on_tissue) {
    mechanics::ModelParams p;
    p.radius = kRadius;
    p.length = 0.3;
    p.initial_q = Loop(Vec3::Zero());
    SceneOptions options;
    options.textures = textures;
    SceneRenderer scene(p, DefaultPalette(), options);
    skin::SkinOptions skin_options;
    skin_options.radius = kRadius;
    std::unique_ptr<skin::Skin> skin = skin::MakeSkin("convolution", skin_options);
    skin->Bind(kPoints);
    skin::Mesh mesh;
    skin->Build(Loop(offset), &mesh);
    if (!on_tissue) mesh.surface.clear();  // the texture then lies in world space
    Laparoscope scope;
    scope.eye = (Vec3(0.0, -0.08, 0.12) + offset).cast<float>();
    scope.target = offset.cast<float>();
    scope.light_range = 0.2f;
    scope.spot_inner_deg = 30.0f;
    scope.spot_outer_deg = 50.0f;
    context_.MakeCurrent();
    scene.Draw(mesh, {}, scope.Matrices(kWidth, kHeight));
    return context_.Frame().clone();
  }

  // Share of the bowel's pixels (those not the background in `a`) whose colour differs by more
  // than `levels` in some channel.
  static double Changed(const cv::Mat& a, const cv::Mat& b, int levels) {
    const cv::Vec4b background = a.at<cv::Vec4b>(0, 0);
    int changed = 0, bowel = 0;
    for (int r = 0; r < a.rows; ++r) {
      for (int c = 0; c < a.cols; ++c) {
        const cv::Vec4b x = a.at<cv::Vec4b>(r, c), y = b.at<cv::Vec4b>(r, c);
        if (x == background) continue;
        ++bowel;
        for (int k = 0; k < 3; ++k) {
          if (std::abs(x[k] - y[k]) > levels) {
            ++changed;
            break;
          }
        }
      }
    }
    EXPECT_GT(bowel, a.rows * a.cols / 20) << "the bowel fills part of the frame";
    return static_cast<double>(changed) / std::max(bowel, 1);
  }

  OffscreenContext context_{kWidth, kHeight};
};

TEST_F(TissueTexture, TheSameSceneDrawsTheSamePixels) {
  const cv::Mat first = Frame(Vec3::Zero(), true, true);
  const cv::Mat second = Frame(Vec3::Zero(), true, true);  // a new renderer, shaders compiled again
  EXPECT_EQ(cv::norm(first, second, cv::NORM_L1), 0.0);
}

TEST_F(TissueTexture, TheSerosaShowsItsVessels) {
  const cv::Mat textured = Frame(Vec3::Zero(), true, true);
  const cv::Mat plain = Frame(Vec3::Zero(), false, true);
  const double changed = Changed(textured, plain, 12);
  EXPECT_GT(changed, 0.03) << "the pattern changes the look of the bowel";
  // and only the bowel: the background stays
  EXPECT_EQ(textured.at<cv::Vec4b>(2, 2), plain.at<cv::Vec4b>(2, 2));
}

TEST_F(TissueTexture, ThePatternRidesOnTheBowel) {
  const Vec3 shift(0.0109, 0.0071, 0.0029);  // 1.56 of the vessels' 7 mm period along x
  const double riding = Changed(Frame(Vec3::Zero(), true, true), Frame(shift, true, true), 20);
  const double plain = Changed(Frame(Vec3::Zero(), false, true), Frame(shift, false, true), 20);
  EXPECT_LT(riding, plain + 0.005)
      << "no more change than the shading alone (rounding at the edges)";
  // control: the same pattern fixed in the world slides over the moving bowel
  const double fixed = Changed(Frame(Vec3::Zero(), true, false), Frame(shift, true, false), 20);
  EXPECT_GT(fixed, riding + 0.01);
  std::printf(
      "bowel pixels changed by a rigid shift: %.4f riding, %.4f plain, %.4f fixed in the world\n",
      riding, plain, fixed);
}

}  // namespace
}  // namespace viscera::render
