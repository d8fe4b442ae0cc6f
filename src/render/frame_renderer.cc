#include "render/frame_renderer.h"

#include <cstdio>

#include "common/check.h"
#include "common/clock.h"
#include "render/gl.h"
#include "skin/hybrid_skin.h"

namespace viscera::render {
namespace {

double MillisSince(int64_t begin) { return static_cast<double>(MonotonicNanos() - begin) * 1e-6; }

skin::SkinOptions WithRadius(skin::SkinOptions options, double radius) {
  options.radius = radius;
  return options;
}

}  // namespace

void ParseFrameSize(const std::string& text, int* width, int* height) {
  int w = 0, h = 0, consumed = 0;
  const bool ok = std::sscanf(text.c_str(), "%dx%d%n", &w, &h, &consumed) == 2 &&
                  consumed == static_cast<int>(text.size()) && w > 0 && h > 0;
  ThrowUnless(ok, "frame size \"", text, "\": expected WIDTHxHEIGHT, e.g. 640x480");
  *width = w;
  *height = h;
}

FrameRenderer::FrameRenderer(const mechanics::ModelParams& params, const FrameOptions& options)
    : context_(options.width, options.height),
      encoder_(options.jpeg_quality),
      skin_(skin::MakeSkin(options.skin, WithRadius(options.skin_options, params.radius))),
      focus_radius_(options.skin_options.hybrid.focus_radius),
      scene_(std::make_unique<SceneRenderer>(params, options.palette, options.scene)) {
  skin_->Bind(static_cast<int>(params.initial_q.rows()));
  width_ = context_.width();
  height_ = context_.height();
}

void FrameRenderer::SetFrameSize(int width, int height) {
  ThrowUnless(width >= 1 && width <= context_.width() && height >= 1 && height <= context_.height(),
              "frame size ", width, "x", height, " is outside 1..", context_.width(), "x",
              context_.height());
  width_ = width;
  height_ = height;
}

cv::Mat FrameRenderer::Frame() {
  const cv::Mat all = context_.Frame();
  if (width_ == context_.width() && height_ == context_.height()) return all;
  // GL's viewport starts at the bottom left; the buffer's first row is the top
  return all(cv::Rect(0, context_.height() - height_, width_, height_));
}

FrameRenderer::~FrameRenderer() = default;

cv::Mat FrameRenderer::Render(const Points& q, std::span<const mechanics::ToolState> tools,
                              const Laparoscope& camera) {
  const CameraMatrices matrices = camera.Matrices(width_, height_);

  // skin: the hybrid's convolution surface follows the scope's look-at point
  int64_t begin = MonotonicNanos();
  if (auto* hybrid = dynamic_cast<skin::HybridSkin*>(skin_.get())) {
    hybrid->SetFocus(camera.target.cast<double>(), focus_radius_);
  }
  skin_->Build(q, &mesh_);
  timings_.skin_ms = MillisSince(begin);

  // draw, and wait for llvmpipe to finish the frame
  begin = MonotonicNanos();
  context_.MakeCurrent();
  glViewport(0, 0, width_, height_);
  scene_->Draw(mesh_, tools, matrices, &q);
  timings_.draw_ms = MillisSince(begin);
  const int64_t drawn = MonotonicNanos();
  cv::Mat frame = Frame();
  timings_.finish_ms = MillisSince(drawn);
  timings_.render_ms = MillisSince(begin);
  return frame;
}

const std::vector<uint8_t>& FrameRenderer::Encode() {
  const int64_t begin = MonotonicNanos();
  // Frame() is a view of the buffer llvmpipe drew into: BGRA, top row first, what
  // OpenCV's JPEG writer takes without a flip or a copy
  const std::vector<uint8_t>& bytes = encoder_.Encode(Frame());
  timings_.encode_ms = MillisSince(begin);
  return bytes;
}

}  // namespace viscera::render
