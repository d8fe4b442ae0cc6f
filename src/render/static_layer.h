#pragma once
/// StaticLayer: the picture of what never moves (the cavity wall, the organs, the targets) as one
/// camera sees it, colour and depth, kept in a framebuffer object of its own. While the camera
/// stays (a scope held still: the usual laparoscope view), a frame starts from a copy of it and
/// draws only what moves; the depth test then hides each moving fragment behind the wall exactly
/// as if everything had been drawn, so the frame is the same picture. The wall's textured
/// fragments, most of a laparoscope's frame, are shaded once per camera instead of once per frame.
#include <Eigen/Core>

#include "render/mesh_renderer.h"

namespace viscera::render {

class StaticLayer {
 public:
  /// @pre a GL >= 3.3 context is current on this thread for the object's whole life.
  StaticLayer();
  ~StaticLayer();
  StaticLayer(const StaticLayer&) = delete;
  StaticLayer& operator=(const StaticLayer&) = delete;

  /// True when the layer holds the picture of `camera` at `width` x `height`.
  bool Holds(const CameraMatrices& camera, int width, int height) const;
  /// Binds the layer's framebuffer (resized if needed) to draw the static scene for `camera`
  /// into; the caller clears and draws, then calls Restore.
  void BeginDrawing(const CameraMatrices& camera, int width, int height);
  /// Binds the framebuffer that was bound before BeginDrawing again.
  void EndDrawing();
  /// Copies the layer's colour and depth into the bound draw framebuffer (same size).
  void CopyToBound() const;
  /// Forgets the picture (the next Holds is false).
  void Invalidate() { valid_ = false; }

 private:
  unsigned framebuffer_ = 0, colour_ = 0, depth_ = 0;
  int width_ = 0, height_ = 0;
  int previous_ = 0;
  bool valid_ = false;
  CameraMatrices camera_;
};

}  // namespace viscera::render
