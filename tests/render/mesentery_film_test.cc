// The mesentery film (SceneRenderer, scenes with [mesentery]): real OSMesa frames of the settled
// cavity, with and without the film. Where the film shows, each pixel is a blend of what lies
// behind it and the film's colour (on the segment between them, not the film's colour alone);
// an opaque film is the negative control (it must not pass for a blend).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include <opencv2/core.hpp>

#include "render/frame_renderer.h"
#include "scene/scene.h"

namespace viscera::render {
namespace {

struct Blend {
  int changed = 0;            // pixels the film changed (> 4 levels)
  int off_segment = 0;        // changed pixels not between the background and the film colour
  double median_share = 0.0;  // how far toward the film colour a changed pixel went (0..1)
};

// The film unlit (ambient 1, no highlight): its colour is its albedo exactly, so a pixel behind
// n layers of opacity a is c0 + (1 - (1 - a)^n) (albedo - c0).
Blend CompareFilm(float opacity) {
  const scene::Scene scene = scene::LoadSceneFile(VISCERA_SOURCE_DIR "/scenes/cavity.toml");
  FrameOptions options;
  options.width = 320;
  options.height = 240;
  options.palette.mesentery.ambient = 1.0f;
  options.palette.mesentery.specular = 0.0f;
  options.palette.mesentery.sheen = 0.0f;
  options.palette.mesentery.opacity = opacity;
  // one film colour: the blend is measured against it (the vessels would vary it)
  options.palette.mesentery.pattern = Pattern::kPlain;
  const Eigen::Vector3f film = options.palette.mesentery.albedo * 255.0f;  // RGB levels
  const Laparoscope scope = LookAtLaparoscope(Vec3(0.0, -0.10, 0.24), Vec3(0.0, 0.0, 0.03));
  const Points& q = scene.model.initial_q;
  cv::Mat with, without;
  {
    FrameRenderer renderer(scene.model, options);
    renderer.Render(q, {}, scope).copyTo(with);
  }
  {
    mechanics::ModelParams bare = scene.model;
    bare.mesentery.reset();
    FrameRenderer renderer(bare, options);
    renderer.Render(q, {}, scope).copyTo(without);
  }
  Blend b;
  std::vector<double> shares;
  for (int y = 0; y < with.rows; ++y) {
    for (int x = 0; x < with.cols; ++x) {
      const cv::Vec4b c = with.at<cv::Vec4b>(y, x), c0 = without.at<cv::Vec4b>(y, x);
      const Eigen::Vector3f now(c[2], c[1], c[0]), before(c0[2], c0[1], c0[0]);
      if ((now - before).cwiseAbs().maxCoeff() <= 4.0f) continue;
      ++b.changed;
      const Eigen::Vector3f toward = film - before;
      const float t = (now - before).dot(toward) / std::max(toward.squaredNorm(), 1.0f);
      const float off = (now - (before + t * toward)).norm();
      if (t < -0.02f || t > 1.02f || off > 4.0f) ++b.off_segment;
      shares.push_back(t);
    }
  }
  if (!shares.empty()) {
    std::nth_element(shares.begin(), shares.begin() + shares.size() / 2, shares.end());
    b.median_share = shares[shares.size() / 2];
  }
  return b;
}

TEST(MesenteryFilm, BlendsTheFilmColourWithWhatIsBehindIt) {
  const Blend b = CompareFilm(0.35f);
  const int pixels = 320 * 240;
  EXPECT_GT(b.changed, pixels / 50) << "the film hardly shows";
  EXPECT_LE(b.off_segment, b.changed / 100)
      << "pixels that are not a blend of the film and the scene behind";
  EXPECT_LT(b.median_share, 0.8) << "the film hides what is behind it";
  EXPECT_GT(b.median_share, 0.3) << "the film is fainter than one layer";
  // negative control: an opaque film replaces what is behind it
  const Blend opaque = CompareFilm(1.0f);
  EXPECT_GT(opaque.median_share, 0.97);
}

}  // namespace
}  // namespace viscera::render
