#include "render/frame_renderer.h"

#include <cstdio>
#include <cstring>
#include <stdexcept>

#include <opencv2/core.hpp>

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
  // the frame's own target: the StaticLayer's formats (GL_RGBA8, GL_DEPTH_COMPONENT24)
  glGenFramebuffers(1, &framebuffer_);
  glGenRenderbuffers(1, &colour_);
  glGenRenderbuffers(1, &depth_);
  glBindRenderbuffer(GL_RENDERBUFFER, colour_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width_, height_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width_, height_);
  glBindRenderbuffer(GL_RENDERBUFFER, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error(
        Cat("FrameRenderer: framebuffer ", width_, "x", height_, " is incomplete"));
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetError();  // none pending before the probe
  glPixelStorei(GL_PACK_INVERT_MESA, GL_TRUE);
  pack_invert_ = glGetError() == GL_NO_ERROR;
}

void FrameRenderer::SetFrameSize(int width, int height) {
  ThrowUnless(width >= 1 && width <= context_.width() && height >= 1 && height <= context_.height(),
              "frame size ", width, "x", height, " is outside 1..", context_.width(), "x",
              context_.height());
  width_ = width;
  height_ = height;
}

void FrameRenderer::ReadFrame() {
  // GL's viewport starts at the bottom left: the frame is the framebuffer's bottom rows
  frame_.create(height_, width_, CV_8UC4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
  if (pack_invert_) {
    glReadPixels(0, 0, width_, height_, GL_BGRA, GL_UNSIGNED_BYTE, frame_.data);
  } else {
    read_.create(height_, width_, CV_8UC4);
    glReadPixels(0, 0, width_, height_, GL_BGRA, GL_UNSIGNED_BYTE, read_.data);
    cv::flip(read_, frame_, 0);
  }
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR)
    throw std::runtime_error(Cat("GL error 0x", std::hex, error, " reading the frame"));
}

FrameRenderer::~FrameRenderer() {
  scene_.reset();  // its GL objects first, like these: the context is still current
  glDeleteRenderbuffers(1, &depth_);
  glDeleteRenderbuffers(1, &colour_);
  glDeleteFramebuffers(1, &framebuffer_);
}

cv::Mat FrameRenderer::Render(const Points& q, std::span<const mechanics::ToolState> tools,
                              const Laparoscope& camera) {
  const CameraMatrices matrices = camera.Matrices(width_, height_);

  // skin: the hybrid's convolution surface follows the scope's look-at point
  const int64_t cpu_begin = ThreadCpuNanos();
  int64_t begin = MonotonicNanos();
  if (auto* hybrid = dynamic_cast<skin::HybridSkin*>(skin_.get())) {
    hybrid->SetFocus(camera.target.cast<double>(), focus_radius_);
  }
  skin_->Build(q, &mesh_);
  timings_.skin_ms = MillisSince(begin);

  // draw, and wait for llvmpipe to finish the frame
  begin = MonotonicNanos();
  context_.MakeCurrent();
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, width_, height_);
  scene_->Draw(mesh_, tools, matrices, &q);
  timings_.draw_ms = MillisSince(begin);
  const int64_t drawn = MonotonicNanos();
  ReadFrame();  // waits for llvmpipe to finish the frame
  timings_.finish_ms = MillisSince(drawn);
  timings_.render_ms = MillisSince(begin);
  timings_.cpu_ms = static_cast<double>(ThreadCpuNanos() - cpu_begin) * 1e-6;
  return frame_;
}

const std::vector<uint8_t>& FrameRenderer::Encode() {
  const int64_t cpu_begin = ThreadCpuNanos();
  const int64_t begin = MonotonicNanos();
  // BGRA, top row first: what OpenCV's JPEG writer takes without a flip or a copy
  ThrowUnless(!frame_.empty(), "FrameRenderer::Encode before any Render");
  const std::vector<uint8_t>& bytes = encoder_.Encode(frame_);
  timings_.encode_ms = MillisSince(begin);
  timings_.cpu_ms += static_cast<double>(ThreadCpuNanos() - cpu_begin) * 1e-6;
  return bytes;
}

}  // namespace viscera::render
