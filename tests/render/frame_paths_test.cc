// The settled cavity through its laparoscope: the frame drawn over the kept picture of the static
// scene, with the intestine culled to the view, against the reference drawing everything every
// frame; the far loops with fewer rings and sides against every ring and side. Decoded JPEGs are
// compared: the intestine's pixel mask and the mean colour.
#include <gtest/gtest.h>

#include <algorithm>
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
  options.scene.integer_exponents = fast;
  options.scene.level_of_detail = false;  // compared on its own below
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

void ExpectSamePicture(const cv::Mat& fast, const cv::Mat& reference, const char* what,
                       double min_overlap = 0.95) {
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
  EXPECT_GE(overlap, min_overlap);
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

// The serosa's noises (the vessels' reach round the tube, the wet film, the bands' waviness) per
// vertex against all of its pattern per fragment, the rest of the frame alike: the same picture
// within the thresholds of ExpectSamePicture (mean difference below one level of 255, pink masks
// overlapping 95 %), for both ring-based skins at viscerad's 16 sides.
TEST(FramePaths, TheSerosaWithItsNoisesPerVertexLooksTheSame) {
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

// The highlights' whole exponents (the bowel's 80 and 5, the wall's 50 and 4, ...) as products of
// squares against GLSL's pow, the rest of the frame alike: the same values up to rounding, so the
// frames differ by far less than a level (mean below 0.05, masks overlapping 99.9 %), for both
// ring-based skins at viscerad's 16 sides. Control: the bowel's sharp lobe at exponent 60 instead
// of 80 (by pow) differs from the reference more than ten times as much.
TEST(FramePaths, TheHighlightsWholeExponentsAsProductsLookTheSame) {
  const mechanics::ModelParams& params = Cavity().model;
  const Points& q = params.initial_q;
  const Laparoscope scope = SceneLaparoscope(params, q, kWidth, kHeight);
  for (const char* skin : {"parametric", "convolution"}) {
    FrameOptions products = Options(true, skin), powers = Options(true, skin);
    powers.scene.integer_exponents = false;
    FrameRenderer a(params, products);
    a.Render(q, {}, scope);
    const cv::Mat fast = Decode(a.Encode());
    FrameRenderer b(params, powers);
    b.Render(q, {}, scope);
    const cv::Mat reference = Decode(b.Encode());
    const std::string what = std::string(skin) + ", exponents as products";
    ExpectSamePicture(fast, reference, what.c_str(), 0.999);
    const double difference = MeanDifference(fast, reference);
    EXPECT_LT(difference, 0.05) << skin;
    // control: a duller sharp lobe on the bowel shows
    FrameOptions duller = powers;
    duller.palette.intestine.shininess = 60.0f;
    FrameRenderer c(params, duller);
    c.Render(q, {}, scope);
    const double control = MeanDifference(Decode(c.Encode()), reference);
    RecordProperty(std::string(skin) + ", exponent 60: mean difference", std::to_string(control));
    EXPECT_GT(control, 10.0 * std::max(difference, 0.005)) << skin;
  }
}

// Pixels of the target's green (as tests/assessment/exposure_render_test.cc): nothing else in the
// abdomen is this green.
int TargetPixels(const cv::Mat& bgr) {
  int count = 0;
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      count += p[1] > p[2] + 40 && p[1] > p[0] + 40 ? 1 : 0;
    }
  }
  return count;
}

// The far loops with fewer rings and sides (SkinDetail, SceneOptions::level_of_detail) against
// every ring and side, the rest of the frame alike, for both ring-based skins at viscerad's 16
// sides: the settled pile (lesion hidden) and the pile moved 3 cm so that it covers part of the
// lesion. The same picture within tighter thresholds than ExpectSamePicture's (masks overlapping
// 97 %; measured 0.977 and 0.977 settled), the lesion hidden in both or seen in both with the
// same pixels within 3 %, and fewer triangles drawn.
TEST(FramePaths, TheFarLoopsWithFewerRingsAndSidesLookTheSame) {
  const mechanics::ModelParams& params = Cavity().model;
  const Laparoscope scope = SceneLaparoscope(params, params.initial_q, kWidth, kHeight);
  Points moved = params.initial_q;
  moved.col(1).array() += 0.03;
  for (const char* skin : {"parametric", "convolution"}) {
    FrameOptions detail = Options(true, skin);
    detail.scene.level_of_detail = true;
    FrameRenderer a(params, detail);
    FrameRenderer b(params, Options(true, skin));
    for (const bool settled : {true, false}) {
      const Points* q = settled ? &params.initial_q : &moved;
      const std::string what = std::string(skin) + (settled ? ", settled" : ", moved");
      a.Render(*q, {}, scope);
      const cv::Mat detailed = Decode(a.Encode());
      b.Render(*q, {}, scope);
      const cv::Mat reference = Decode(b.Encode());
      ExpectSamePicture(detailed, reference, what.c_str(), 0.97);
      const int target = TargetPixels(detailed), target_full = TargetPixels(reference);
      RecordProperty(what + ": target pixels",
                     std::to_string(target) + " of " + std::to_string(target_full));
      if (settled) {
        EXPECT_EQ(target_full, 0) << what;  // the lesion is under the pile
        EXPECT_EQ(target, 0) << what;
      } else {
        EXPECT_GT(target_full, 50) << what;  // part of it shows past the moved pile
        EXPECT_NEAR(target, target_full, 0.03 * target_full) << what;
      }
      // the renderer's count: fewer of the skin's triangles drawn
      const long drawn = a.scene().intestine_counts().triangles_drawn;
      const long drawn_full = b.scene().intestine_counts().triangles_drawn;
      RecordProperty(what + ": triangles drawn",
                     std::to_string(drawn) + " of " + std::to_string(drawn_full));
      EXPECT_LT(drawn, drawn_full * 9 / 10) << what;
      // the 20 pieces of tube nearest the scope keep every side; the far third of the pieces
      // drawn has fewer triangles per ring than the near third, and fewer than the full skin
      std::vector<SkinDetail::Block> blocks;
      for (const SkinDetail::Block& block : a.scene().intestine_blocks()) {
        if (block.drawn) blocks.push_back(block);
      }
      ASSERT_GT(blocks.size(), 60u);
      std::sort(blocks.begin(), blocks.end(),
                [](const auto& x, const auto& y) { return x.depth < y.depth; });
      for (size_t k = 0; k < 20; ++k) {
        EXPECT_EQ(kDetailLevels[static_cast<size_t>(blocks[k].level)].side_step, 1) << what;
      }
      auto per_ring = [&blocks](size_t from, size_t to) {
        double triangles = 0.0, rings = 0.0;
        for (size_t k = from; k < to; ++k) {
          triangles += blocks[k].triangles;
          rings += blocks[k].last_ring - blocks[k].first_ring;
        }
        return triangles / rings;
      };
      const size_t third = blocks.size() / 3;
      const double near = per_ring(0, third), far = per_ring(blocks.size() - third, blocks.size());
      RecordProperty(what + ": triangles per ring, near and far third",
                     std::to_string(near) + ", " + std::to_string(far));
      EXPECT_LT(far, near) << what;
      EXPECT_LT(far, 0.85 * 2 * 16) << what;
    }
  }
}

// The tools where the load tester moves them: jaws open, tips on a 1 cm circle 0.15 m above the
// middle of the pile, at angle `a`.
// The scene's tools with their tips 1 cm apart on a circle at angle `a`, 8 cm above where the
// scope looks: in view, above the pile.
std::vector<mechanics::ToolState> ToolsAt(const mechanics::ModelParams& params,
                                          const Laparoscope& scope, double a) {
  std::vector<mechanics::ToolState> tools(params.tools.size());
  const Vec3 centre = scope.target.cast<double>() + Vec3(0.0, 0.0, 0.08);
  for (size_t i = 0; i < tools.size(); ++i) {
    tools[i].initialized = true;
    tools[i].tip =
        centre + Vec3(0.01 * std::cos(a) + 0.03 * static_cast<double>(i), 0.01 * std::sin(a), 0.0);
  }
  return tools;
}

// BGRA as drawn (before the JPEG): the kept picture must give the reference's pixels exactly.
double PixelsApart(FrameRenderer& a, FrameRenderer& b, const Points& q,
                   const std::vector<mechanics::ToolState>& tools, const Laparoscope& scope) {
  const cv::Mat fast = a.Render(q, tools, scope).clone();
  return cv::norm(fast, b.Render(q, tools, scope), cv::NORM_L1);
}

// The picture of the static scene and the intestine kept while the bowel rests and a tool
// moves: the frame is the reference's pixel for pixel (the tools drawn over a copy of what the
// reference draws before them); a bowel moved by a small fraction of a pixel keeps the picture
// and differs from the reference by far less than a level; moved further, or damaged, the
// intestine is drawn again and the frame is the reference's again.
TEST(FramePaths, TheKeptIntestineWhileTheBowelRestsDrawsTheReferenceFrame) {
  const mechanics::ModelParams& params = Cavity().model;
  ASSERT_FALSE(params.tools.empty());
  const Points& q = params.initial_q;
  const Laparoscope scope = SceneLaparoscope(params, q, kWidth, kHeight);
  for (const char* skin : {"parametric", "convolution"}) {
    SCOPED_TRACE(skin);
    FrameOptions kept = Options(true, skin);
    kept.scene.level_of_detail = true;
    FrameOptions drawn = kept;
    drawn.scene.keep_intestine = false;
    FrameRenderer a(params, kept), b(params, drawn);
    EXPECT_EQ(PixelsApart(a, b, q, ToolsAt(params, scope, 0.0), scope), 0.0);
    EXPECT_FALSE(a.scene().intestine_kept());  // the first frame draws it
    // the tools move, the bowel rests
    const std::vector<mechanics::ToolState> moved_tools = ToolsAt(params, scope, 1.0);
    const double apart = PixelsApart(a, b, q, moved_tools, scope);
    EXPECT_TRUE(a.scene().intestine_kept());
    if (std::string(skin) == "parametric") {
      EXPECT_EQ(apart, 0.0);
    } else {
      // the convolution skin's build starts from its last one: the same skeleton built again
      // moves its surface by far less than a pixel, and the kept picture is the first build's
      EXPECT_LT(apart, 0.001 * kWidth * kHeight);
    }
    // control: the tools' move shows in the frame
    FrameRenderer c(params, drawn);
    const cv::Mat before = c.Render(q, ToolsAt(params, scope, 0.0), scope).clone();
    EXPECT_GT(cv::norm(before, c.Render(q, moved_tools, scope), cv::NORM_L1), 0.0);

    // 10 um, within the tolerance: the frame shows the bowel where it was drawn (only the
    // mesentery's film, drawn every frame, follows), as near the bowel drawn afresh as two
    // fresh frames of so small a move are to each other
    const cv::Mat at_q = Decode(b.Encode());
    const Points nudged = q.rowwise() + Eigen::RowVector3d(1e-5, 0.0, 0.0);
    a.Render(nudged, moved_tools, scope);
    EXPECT_TRUE(a.scene().intestine_kept());
    const cv::Mat kept_frame = Decode(a.Encode());
    b.Render(nudged, moved_tools, scope);
    const cv::Mat reference = Decode(b.Encode());
    ExpectSamePicture(kept_frame, reference, "nudged");
    const double fresh_apart = MeanDifference(at_q, reference);
    EXPECT_LT(MeanDifference(kept_frame, at_q), 0.2 * fresh_apart);
    EXPECT_LT(MeanDifference(kept_frame, reference), 1.2 * fresh_apart);

    // 2 mm: drawn again, the reference's pixels
    const Points shifted = q.rowwise() + Eigen::RowVector3d(2e-3, 0.0, 0.0);
    EXPECT_EQ(PixelsApart(a, b, shifted, moved_tools, scope), 0.0);
    EXPECT_FALSE(a.scene().intestine_kept());
    // damaged: drawn again in two colours
    a.SetDamage({{0.2, 0.4}});
    b.SetDamage({{0.2, 0.4}});
    EXPECT_EQ(PixelsApart(a, b, shifted, moved_tools, scope), 0.0);
    EXPECT_FALSE(a.scene().intestine_kept());
  }
}

}  // namespace
}  // namespace viscera::render
