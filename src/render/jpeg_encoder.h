#pragma once
/// JpegEncoder: 8-bit images to JPEG bytes with libjpeg-turbo (baseline, 4:2:0, libjpeg's
/// tables at the given quality: the bytes OpenCV's writer gives), reusing its buffers.
#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace viscera::render {

class JpegEncoder {
 public:
  /// @param quality JPEG quality, 1 (smallest) .. 100 (best).
  /// @throws InputError when quality is outside 1..100.
  explicit JpegEncoder(int quality = 85);

  /// Encodes `image`: CV_8UC1 (grey), CV_8UC3 (BGR) or CV_8UC4 (BGRA, alpha dropped),
  /// top row first, any row stride. OffscreenContext::Frame() is already in that
  /// layout, so frames go in without a flip or a colour conversion: libjpeg-turbo reads
  /// BGRA rows as they are (OpenCV's writer copied each row to BGR first).
  /// @return the JPEG bytes, valid until the next Encode; the buffer keeps its
  ///         capacity, so steady-state encoding does not allocate it again.
  /// @throws InputError for an empty image or another pixel type.
  /// @throws std::runtime_error when libjpeg fails to encode.
  const std::vector<uint8_t>& Encode(const cv::Mat& image);

  int quality() const { return quality_; }

 private:
  int quality_;
  std::vector<uint8_t> buffer_;  // libjpeg writes here (the raw image's size and a margin)
  std::vector<uint8_t> bytes_;
};

}  // namespace viscera::render
