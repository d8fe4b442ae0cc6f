#include "render/jpeg_encoder.h"

#include <algorithm>
#include <csetjmp>
#include <cstdio>  // jpeglib.h needs FILE and size_t first
#include <stdexcept>
#include <string>

#include <jpeglib.h>

#ifndef JCS_EXTENSIONS
#error "JpegEncoder needs libjpeg-turbo's JCS_EXT_BGR and JCS_EXT_BGRA"
#endif

#include "common/check.h"

namespace viscera::render {
namespace {

// libjpeg's errors end in a longjmp back to Compress (its default handler exits the process);
// no C++ object with a destructor lives between the setjmp and the libjpeg calls.
struct ErrorManager {
  jpeg_error_mgr manager;
  std::jmp_buf back;
  char message[JMSG_LENGTH_MAX];
};

void OnError(j_common_ptr info) {
  auto* errors = reinterpret_cast<ErrorManager*>(info->err);
  (*info->err->format_message)(info, errors->message);
  std::longjmp(errors->back, 1);
}

// The compressed bytes go to a buffer the encoder keeps (its capacity: the raw image and a
// margin, more than a JPEG of it takes); a larger one than that fails rather than reallocating
// under libjpeg.
struct Destination {
  jpeg_destination_mgr manager;
  uint8_t* buffer;
  size_t capacity;
};

void InitDestination(j_compress_ptr info) {
  auto* d = reinterpret_cast<Destination*>(info->dest);
  d->manager.next_output_byte = d->buffer;
  d->manager.free_in_buffer = d->capacity;
}

boolean EmptyOutputBuffer(j_compress_ptr info) {
  auto* errors = reinterpret_cast<ErrorManager*>(info->err);
  std::snprintf(errors->message, sizeof errors->message, "the JPEG outgrew its buffer");
  std::longjmp(errors->back, 1);
}

void TermDestination(j_compress_ptr) {}

// Compresses rows of `image` (grey, BGR or BGRA) into `buffer`; returns the bytes written, or 0
// with *message set when libjpeg failed.
size_t Compress(const cv::Mat& image, int quality, uint8_t* buffer, size_t capacity,
                char* message) {
  jpeg_compress_struct info{};
  ErrorManager errors{};
  info.err = jpeg_std_error(&errors.manager);
  errors.manager.error_exit = OnError;
  Destination destination{};
  destination.buffer = buffer;
  destination.capacity = capacity;
  destination.manager.init_destination = InitDestination;
  destination.manager.empty_output_buffer = EmptyOutputBuffer;
  destination.manager.term_destination = TermDestination;
  if (setjmp(errors.back) != 0) {
    jpeg_destroy_compress(&info);
    std::copy(errors.message, errors.message + JMSG_LENGTH_MAX, message);
    return 0;
  }
  jpeg_create_compress(&info);
  info.dest = &destination.manager;
  info.image_width = static_cast<JDIMENSION>(image.cols);
  info.image_height = static_cast<JDIMENSION>(image.rows);
  info.input_components = image.channels();
  // libjpeg-turbo reads OpenCV's channel orders as they are: no conversion pass
  info.in_color_space =
      image.channels() == 4 ? JCS_EXT_BGRA : (image.channels() == 3 ? JCS_EXT_BGR : JCS_GRAYSCALE);
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, quality, TRUE);
  jpeg_start_compress(&info, TRUE);
  while (info.next_scanline < info.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(image.ptr<uint8_t>(static_cast<int>(info.next_scanline)));
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  const size_t written = capacity - destination.manager.free_in_buffer;
  jpeg_destroy_compress(&info);
  return written;
}

}  // namespace

JpegEncoder::JpegEncoder(int quality) : quality_(quality) {
  ThrowUnless(quality >= 1 && quality <= 100, "JPEG quality ", quality, " is outside 1..100");
}

const std::vector<uint8_t>& JpegEncoder::Encode(const cv::Mat& image) {
  ThrowUnless(!image.empty(), "JpegEncoder::Encode: empty image");
  const int type = image.type();
  ThrowUnless(type == CV_8UC1 || type == CV_8UC3 || type == CV_8UC4,
              "JpegEncoder::Encode: pixel type ", cv::typeToString(type),
              " is not 8-bit grey, BGR or BGRA");
  const size_t capacity = image.total() * image.elemSize() + 65536;
  if (buffer_.size() < capacity) buffer_.resize(capacity);
  char message[JMSG_LENGTH_MAX] = {};
  const size_t written = Compress(image, quality_, buffer_.data(), buffer_.size(), message);
  if (written == 0) throw std::runtime_error(Cat("libjpeg failed to encode a JPEG: ", message));
  bytes_.assign(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(written));
  return bytes_;
}

}  // namespace viscera::render
