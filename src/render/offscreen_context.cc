#include "render/offscreen_context.h"

#include <malloc.h>

#include <cstdlib>
#include <mutex>
#include <stdexcept>

#include "common/check.h"
#include "render/gl.h"

namespace viscera::render {
namespace {

constexpr int kMaxSize = 8192;

OSMesaContext CreateContext(bool core) {
  // Colour BGRA so that OpenCV takes the buffer as it is; depth for meshes.
  const int common[] = {OSMESA_FORMAT,       OSMESA_BGRA, OSMESA_DEPTH_BITS, 24,
                        OSMESA_STENCIL_BITS, 0,           OSMESA_ACCUM_BITS, 0};
  std::vector<int> attribs(std::begin(common), std::end(common));
  if (core) {
    attribs.insert(attribs.end(),
                   {OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 3,
                    OSMESA_CONTEXT_MINOR_VERSION, 3});
  }
  attribs.push_back(0);
  return OSMesaCreateContextAttribs(attribs.data(), nullptr);
}

}  // namespace

void LimitRasterizerThreads() { ::setenv("LP_NUM_THREADS", "0", /*overwrite=*/0); }

void KeepRenderMemoryMapped() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (std::getenv("MALLOC_MMAP_THRESHOLD_") != nullptr ||
        std::getenv("MALLOC_TRIM_THRESHOLD_") != nullptr)
      return;
    ::mallopt(M_MMAP_THRESHOLD, 16 << 20);
    ::mallopt(M_TRIM_THRESHOLD, 64 << 20);
  });
}

OffscreenContext::OffscreenContext(int width, int height)
    : width_(width), height_(height), owner_(std::this_thread::get_id()) {
  ThrowUnless(width >= 1 && width <= kMaxSize && height >= 1 && height <= kMaxSize, "frame size ",
              width, "x", height, " is outside 1..", kMaxSize);
  LimitRasterizerThreads();
  KeepRenderMemoryMapped();
  pixels_.assign(static_cast<size_t>(width) * static_cast<size_t>(height) * 4, 0);

  OSMesaContext context = CreateContext(/*core=*/true);
  core_profile_ = context != nullptr;
  if (context == nullptr) context = CreateContext(/*core=*/false);
  if (context == nullptr) throw std::runtime_error("OSMesa could not create a GL context");
  context_ = context;
  MakeCurrent();

  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  gl_version_ = version != nullptr ? version : "";
  GLint major = 0;
  GLint minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  gl_version_number_ = major * 10 + minor;
  glViewport(0, 0, width_, height_);
}

OffscreenContext::~OffscreenContext() {
  if (context_ != nullptr) OSMesaDestroyContext(static_cast<OSMesaContext>(context_));
}

void OffscreenContext::MakeCurrent() {
  CheckThread();
  auto* context = static_cast<OSMesaContext>(context_);
  if (!OSMesaMakeCurrent(context, pixels_.data(), GL_UNSIGNED_BYTE, width_, height_)) {
    throw std::runtime_error(Cat("OSMesaMakeCurrent failed for ", width_, "x", height_));
  }
  // Top row first: the layout image codecs expect, so frames need no flip.
  OSMesaPixelStore(OSMESA_Y_UP, 0);
}

cv::Mat OffscreenContext::Frame() {
  CheckThread();
  // OSMesa copies the rendered image into pixels_ when GL work completes.
  glFinish();
  return cv::Mat(height_, width_, CV_8UC4, pixels_.data());
}

void OffscreenContext::CheckThread() const { VISCERA_DEMAND(owner_ == std::this_thread::get_id()); }

}  // namespace viscera::render

#if defined(__SANITIZE_ADDRESS__)
// Mesa 22.3's OSMesa never frees ~480 bytes per process and ~200 bytes per context
// created and destroyed (measured with a bare OSMesa create/destroy loop): harmless for
// one context per session, but LeakSanitizer would fail every binary that renders.
// Only allocations made inside libOSMesa are suppressed.
extern "C" const char* __lsan_default_suppressions() { return "leak:libOSMesa.so\n"; }
#endif
