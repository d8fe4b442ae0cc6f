#include "render/static_layer.h"

#include <stdexcept>

#include "common/check.h"
#include "render/gl.h"

namespace viscera::render {
namespace {

bool SameCamera(const CameraMatrices& a, const CameraMatrices& b) {
  return a.view == b.view && a.projection == b.projection && a.light_range == b.light_range &&
         a.spot_inner_deg == b.spot_inner_deg && a.spot_outer_deg == b.spot_outer_deg;
}

}  // namespace

StaticLayer::StaticLayer() {
  glGenFramebuffers(1, &framebuffer_);
  glGenRenderbuffers(1, &colour_);
  glGenRenderbuffers(1, &depth_);
}

StaticLayer::~StaticLayer() {
  glDeleteRenderbuffers(1, &depth_);
  glDeleteRenderbuffers(1, &colour_);
  glDeleteFramebuffers(1, &framebuffer_);
}

bool StaticLayer::Holds(const CameraMatrices& camera, int width, int height) const {
  return valid_ && width == width_ && height == height_ && SameCamera(camera, camera_);
}

void StaticLayer::BeginDrawing(const CameraMatrices& camera, int width, int height) {
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  if (width != width_ || height != height_) {
    glBindRenderbuffer(GL_RENDERBUFFER, colour_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      glBindFramebuffer(GL_FRAMEBUFFER, static_cast<unsigned>(previous_));
      throw std::runtime_error(
          Cat("StaticLayer: framebuffer ", width, "x", height, " is incomplete"));
    }
    width_ = width;
    height_ = height;
  }
  camera_ = camera;
  valid_ = true;
}

void StaticLayer::EndDrawing() {
  glBindFramebuffer(GL_FRAMEBUFFER, static_cast<unsigned>(previous_));
}

void StaticLayer::CopyToBound() const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
  glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_,
                    GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR)
    throw std::runtime_error(Cat("GL error 0x", std::hex, error, " copying the static layer"));
}

}  // namespace viscera::render
