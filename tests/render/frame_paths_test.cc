// The settled cavity through its laparoscope: the frame drawn over the kept picture of the static
// scene, with the intestine culled to the view, against the reference drawing everything every
// frame. Decoded JPEGs are compared: the intestine's pixel mask and the mean colour.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "render/frame_renderer.h"
#include "render/port_scope.h"
#include "scene/scene.h"

namespace viscera::render {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;

const scene::Scene& Cavity() {
  static const scene::Scene scene =
      scene::LoadSceneFile(VISCERA_SOURCE_DIR "/scenes/cavity.toml");  // settled
  return scene;
}

FrameOptions Options(bool fast, const std::string& skin = "convolution") {
  FrameOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.skin = skin;
  options.skin_options.convolution.sides = 16;  // viscerad's --skin-sides
  options.skin_options.parametric.sides = 16;
  options.scene.static_layer = fast;
  options.scene.cull_intestine = fast;
  options.scene.serosa_per_vertex = fast;
  return options;
}

cv::Mat Decode(const std::vector<uint8_t>& jpeg) { return cv::imdecode(jpeg, cv::IMREAD_COLOR); }

// The bowel's pink (as tests/e2e/client_render_test.py): (r - g) / r in 0.33..0.6, g within
// 0.04 r of b.
cv::Mat IntestineMask(const cv::Mat& bgr) {
  cv::Mat mask(bgr.size(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      const double b = p[0], g = p[1], r = p[2];
      if (r < 30) continue;
      const double red = (r - g) / r;
      if (red >= 0.33 && red <= 0.6 && std::abs(g - b) <= 0.04 * r) mask.at<uint8_t>(y, x) = 255;
    }
  }
  return mask;
}

double Overlap(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat both, either;
  cv::bitwise_and(a, b, both);
  cv::bitwise_or(a, b, either);
  return static_cast<double>(cv::countNonZero(both)) / std::max(1, cv::countNonZero(either));
}

double MeanDifference(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  const cv::Scalar m = cv::mean(d);
  return (m[0] + m[1] + m[2]) / 3.0;
}

void ExpectSamePicture(const cv::Mat& fast, const cv::Mat& reference, const char* what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(fast.size(), reference.size());
  const cv::Mat mask = IntestineMask(reference);
  // the scope sees a good part of the pile: the comparison means something
  ASSERT_GT(cv::countNonZero(mask), kWidth * kHeight / 10);
  const double overlap = Overlap(IntestineMask(fast), mask);
  const double difference = MeanDifference(fast, reference);
  testing::Test::RecordProperty(std::string(what) + ": overlap", std::to_string(overlap));
  testing::Test::RecordProperty(std::string(what) + ": mean difference",
                                std::to_string(difference));
  EXPECT_GE(overlap, 0.95);
  EXPECT_LT(difference, 1.0);  // levels of 255, mean over all pixels
}

TEST(FramePaths, TheKeptStaticPictureAndTheCulledSkinDrawTheReferenceFrame) {
  const scene::Scene& cavity = Cavity();
  const mechanics::ModelParams& params = cavity.model;
  const Points& q = params.initial_q;
  const Laparoscope scope = SceneLaparoscope(params, q, kWidth, kHeight);
  Laparoscope moved = scope;
  moved.eye += Eigen::Vector3f(0.02f, 0.0f, 0.01f);

  std::vector<cv::Mat> fast, reference;
  {
    FrameRenderer renderer(params, Options(true));
    for (const Laparoscope& s : {scope, scope, moved}) {
      renderer.Render(q, {}, s);
      fast.push_back(Decode(renderer.Encode()));
    }
    // the chunks left out were outside the view: some were, at the scope's close view
    EXPECT_LT(renderer.scene().intestine_counts().triangles_drawn,
              renderer.scene().intestine_counts().triangles);
  }
  {
    FrameRenderer renderer(params, Options(false));
    for (const Laparoscope& s : {scope, moved}) {
      renderer.Render(q, {}, s);
      reference.push_back(Decode(renderer.Encode()));
    }
  }
  ExpectSamePicture(fast[0], reference[0], "first frame: the static picture drawn");
  ExpectSamePicture(fast[1], reference[0], "second frame: over the kept static picture");
  ExpectSamePicture(fast[2], reference[1], "the scope moved: the static picture drawn again");
  // control: the comparison sees a moved scope
  EXPECT_LT(Overlap(IntestineMask(fast[2]), IntestineMask(reference[0])), 0.95);
}

// The serosa's slow terms (the vessels' reach round the tube, the wet film) per vertex against
// all of its pattern per fragment, the rest of the frame alike: the same picture within the
// thresholds of ExpectSamePicture (mean difference below one level of 255, pink masks overlapping
// 95 %), for both ring-based skins at viscerad's 16 sides.
TEST(FramePaths, TheSerosaWithItsSlowTermsPerVertexLooksTheSame) {
  const mechanics::ModelParams& params = Cavity().model;
  const Points& q = params.initial_q;
  const Laparoscope scope = SceneLaparoscope(params, q, kWidth, kHeight);
  for (const char* skin : {"parametric", "convolution"}) {
    FrameOptions per_vertex = Options(false, skin), per_fragment = Options(false, skin);
    per_vertex.scene.serosa_per_vertex = true;
    FrameRenderer a(params, per_vertex);
    a.Render(q, {}, scope);
    const cv::Mat fast = Decode(a.Encode());
    FrameRenderer b(params, per_fragment);
    b.Render(q, {}, scope);
    const cv::Mat reference = Decode(b.Encode());
    ExpectSamePicture(fast, reference, skin);
    // control: the pattern shows (the frame differs from the same frame without textures)
    FrameOptions plain = per_fragment;
    plain.scene.textures = false;
    FrameRenderer c(params, plain);
    c.Render(q, {}, scope);
    EXPECT_GT(MeanDifference(Decode(c.Encode()), reference), 2.0 * MeanDifference(fast, reference));
  }
}

}  // namespace
}  // namespace viscera::render
