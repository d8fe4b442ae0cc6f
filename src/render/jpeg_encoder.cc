#include "render/jpeg_encoder.h"

#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "common/check.h"

namespace viscera::render {

JpegEncoder::JpegEncoder(int quality) : quality_(quality) {
  ThrowUnless(quality >= 1 && quality <= 100, "JPEG quality ", quality, " is outside 1..100");
  params_ = {cv::IMWRITE_JPEG_QUALITY, quality};
}

const std::vector<uint8_t>& JpegEncoder::Encode(const cv::Mat& image) {
  ThrowUnless(!image.empty(), "JpegEncoder::Encode: empty image");
  const int type = image.type();
  ThrowUnless(type == CV_8UC1 || type == CV_8UC3 || type == CV_8UC4,
              "JpegEncoder::Encode: pixel type ", cv::typeToString(type),
              " is not 8-bit grey, BGR or BGRA");
  if (!cv::imencode(".jpg", image, bytes_, params_)) {
    throw std::runtime_error("OpenCV failed to encode a JPEG");
  }
  return bytes_;
}

}  // namespace viscera::render
