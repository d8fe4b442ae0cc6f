#pragma once
/// OffscreenContext: an OSMesa (llvmpipe) GL context rendering into memory it owns.
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace viscera::render {

/// Makes llvmpipe rasterize in the rendering thread itself (LP_NUM_THREADS=0) unless the
/// environment already says otherwise. llvmpipe's default is one rasterizer thread per
/// core; on a 2-core server those threads would compete with the mechanics threads,
/// whose deadlines matter more than frame rate. With 0 the render cost stays in the
/// render thread: one core at most, visible in its CPU clock, scheduled like any thread.
/// llvmpipe reads the variable once, when the process's first context is created.
/// @pre no other thread reads or writes the environment meanwhile (setenv is not
///      thread-safe): call it, or create the first context, before starting threads.
void LimitRasterizerThreads();

/// Keeps the memory llvmpipe allocates and frees in every frame mapped between frames.
/// llvmpipe's draw module and binner malloc several MB per draw (vertex shader outputs,
/// the binned scene) and free them at the end of the frame; with glibc's defaults such
/// blocks are fresh mmaps, so every page faults (and is zeroed) again in every frame:
/// ~30 % of the render time on the cavity scene (docs/rendering.md). This sets glibc's
/// mmap threshold to 16 MB and its trim threshold to 64 MB, so those blocks are reused
/// from the heap; a process keeps at most ~64 MB more mapped. Nothing changes when the
/// environment already sets MALLOC_MMAP_THRESHOLD_ or MALLOC_TRIM_THRESHOLD_. The
/// mechanics allocate nothing in steady state, so they do not notice.
/// Safe to call from any thread, any number of times (the first call acts).
void KeepRenderMemoryMapped();

/// One GL context with a BGRA8 colour buffer and a 24-bit depth buffer, current on the
/// thread that created it. Asks for GL 3.3 core; falls back to OSMesa's default
/// profile when the core request fails. Rows are stored top row first (OSMESA_Y_UP
/// off), so Frame() goes to the JPEG encoder with no flip and no copy.
class OffscreenContext {
 public:
  /// Creates the context and makes it current on the calling thread.
  /// Calls LimitRasterizerThreads() and KeepRenderMemoryMapped() first.
  /// @throws InputError unless 1 <= width, height <= 8192.
  /// @throws std::runtime_error when OSMesa cannot create or bind the context.
  OffscreenContext(int width, int height);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  /// Binds the context again (after another context was made current on this thread).
  /// @pre called on the creating thread (OSMesa contexts belong to one thread).
  void MakeCurrent();

  /// Finishes pending GL work and returns the frame: #height by #width, CV_8UC4 (BGRA),
  /// top row first. A view of this context's buffer (no copy): valid until the next
  /// draw or the context's destruction.
  /// @pre called on the creating thread.
  cv::Mat Frame();

  int width() const { return width_; }
  int height() const { return height_; }
  /// GL_VERSION as reported by the driver, e.g. "4.5 (Core Profile) Mesa 22.3.6".
  const std::string& gl_version() const { return gl_version_; }
  /// Major * 10 + minor of the context obtained, e.g. 45.
  int gl_version_number() const { return gl_version_number_; }
  bool core_profile() const { return core_profile_; }

 private:
  void CheckThread() const;

  int width_;
  int height_;
  std::vector<uint8_t> pixels_;  // #height * #width * 4 bytes, BGRA, top row first
  void* context_ = nullptr;      // OSMesaContext; void* keeps GL headers out of ours
  std::thread::id owner_;
  std::string gl_version_;
  int gl_version_number_ = 0;
  bool core_profile_ = false;
};

}  // namespace viscera::render
