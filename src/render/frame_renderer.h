#pragma once
/// FrameRenderer: everything a render thread needs to turn skeleton snapshots into JPEG
/// frames — its OSMesa context, a skin, the scene renderer and a JPEG encoder. Made,
/// used and destroyed on one thread (the OSMesa context belongs to it).
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "mechanics/model_params.h"
#include "mechanics/state.h"
#include "render/jpeg_encoder.h"
#include "render/laparoscope.h"
#include "render/offscreen_context.h"
#include "render/scene_renderer.h"
#include "skin/skin.h"

namespace viscera::render {

struct FrameOptions {
  int width = 640;  ///< pixels
  int height = 480;
  int jpeg_quality = 85;  ///< 1..100
  /// "parametric", "implicit", "convolution" or "hybrid" (focus at the camera's look-at).
  std::string skin = "parametric";
  /// The skin's own options; `radius` is replaced by the scene's tube radius.
  skin::SkinOptions skin_options;
  Palette palette = DefaultPalette();
  SceneOptions scene;
};

/// Costs of the last frame, milliseconds of wall time. With LP_NUM_THREADS=0 (the
/// default, see LimitRasterizerThreads) all of it is spent in the calling thread.
struct FrameTimings {
  double skin_ms = 0.0;    ///< skin Build
  double render_ms = 0.0;  ///< upload, draw and glFinish: draw_ms + finish_ms
  double draw_ms = 0.0;    ///< the intestine's culling, the uploads and the draw calls
  double finish_ms = 0.0;  ///< glFinish: what llvmpipe still rasterizes and shades
  double encode_ms = 0.0;  ///< JPEG
  /// The calling thread's CPU time for the frame (skin, draw, read-back, and the JPEG once
  /// Encode ran): what the frame took of a core, without the time the thread waited for one
  /// while other threads ran (another stream's frames sharing the core). With LP_NUM_THREADS
  /// >= 1 it leaves out llvmpipe's rasterizer threads.
  double cpu_ms = 0.0;
};

/// Parses a frame size "WIDTHxHEIGHT" (e.g. "640x480").
/// @throws InputError when the text is not two positive integers joined by 'x'.
void ParseFrameSize(const std::string& text, int* width, int* height);

class FrameRenderer {
 public:
  /// Creates the context (current on the calling thread), binds the skin to the scene's
  /// skeleton and uploads the obstacles.
  /// @pre `params` is valid (a Model was built from it).
  /// @throws InputError for a bad size, quality or skin name; std::runtime_error when
  ///         OSMesa or GL fail.
  FrameRenderer(const mechanics::ModelParams& params, const FrameOptions& options);
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  /// Skins the control points `q` (#N by 3, m), draws the scene with `tools` (State::tools,
  /// or empty) from `camera`, and returns the frame: #height by #width BGRA, top row first,
  /// a view of the renderer's buffer, valid until the next Render.
  /// @pre called on the creating thread.
  /// @throws InputError when q has another row count or is not finite.
  cv::Mat Render(const Points& q, std::span<const mechanics::ToolState> tools,
                 const Laparoscope& camera);
  cv::Mat Render(const mechanics::State& state, const Laparoscope& camera) {
    return Render(state.q, state.tools, camera);
  }

  /// Draws the next frames at `width` x `height` (at most the context's size; the frame a
  /// corner of the framebuffer): a smaller stream without a new context.
  /// @throws InputError for a size outside 1..the context's.
  void SetFrameSize(int width, int height);

  /// The last frame as JPEG bytes, encoded straight from the buffer Render returned; valid
  /// until the next Encode.
  const std::vector<uint8_t>& Encode();

  /// Parts of the bowel drawn in the damage colour (SceneRenderer::SetDamage).
  void SetDamage(std::vector<std::pair<double, double>> ranges) {
    scene_->SetDamage(std::move(ranges));
  }

  const FrameTimings& timings() const { return timings_; }
  const skin::Mesh& mesh() const { return mesh_; }
  const skin::Skin& skin() const { return *skin_; }
  const SceneRenderer& scene() const { return *scene_; }
  OffscreenContext& context() { return context_; }
  int width() const { return width_; }  ///< of the frames drawn now
  int height() const { return height_; }

 private:
  OffscreenContext context_;  // first: everything below needs it current
  JpegEncoder encoder_;
  std::unique_ptr<skin::Skin> skin_;
  double focus_radius_ = 0.0;  // hybrid skin
  std::unique_ptr<SceneRenderer> scene_;
  skin::Mesh mesh_;
  FrameTimings timings_;
  int width_ = 0, height_ = 0;
  // The frames are drawn into a framebuffer object of the renderer's own, not the context's
  // buffer: its formats are the StaticLayer's, so that llvmpipe copies the static picture
  // with a memcpy (into the context's BGRA buffer it would draw a textured quad over the
  // whole frame: ~3 ms at 640x480); glReadPixels then swizzles it into BGRA on the CPU.
  unsigned framebuffer_ = 0, colour_ = 0, depth_ = 0;
  bool pack_invert_ = false;  // GL_MESA_pack_invert: glReadPixels returns the top row first
  cv::Mat frame_;             // the last frame: BGRA, top row first
  cv::Mat read_;              // without GL_MESA_pack_invert: the frame bottom row first
  void ReadFrame();
};

}  // namespace viscera::render
