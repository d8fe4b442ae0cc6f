#include "client/jpeg_header.h"

#include "common/check.h"

namespace viscera::client {

bool JpegSize(const uint8_t* data, size_t size, int* width, int* height) {
  if (size < 4 || data[0] != 0xFF || data[1] != 0xD8) return false;  // SOI
  size_t i = 2;
  while (i + 4 <= size) {
    if (data[i] != 0xFF) return false;
    const uint8_t marker = data[i + 1];
    if (marker == 0xFF) {  // fill byte
      ++i;
      continue;
    }
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) {  // no length
      i += 2;
      continue;
    }
    if (marker == 0xD9 || marker == 0xDA) return false;  // EOI or scan before any frame header
    const size_t length = (static_cast<size_t>(data[i + 2]) << 8) | data[i + 3];
    if (length < 2 || i + 2 + length > size) return false;
    // SOF0..SOF15 except DHT (C4), JPG (C8) and DAC (CC): precision, height, width
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
      if (length < 7) return false;
      *height = (data[i + 5] << 8) | data[i + 6];
      *width = (data[i + 7] << 8) | data[i + 8];
      return true;
    }
    i += 2 + length;
  }
  return false;
}

std::string JpegProblem(const uint8_t* data, size_t size, int width, int height) {
  int w = 0, h = 0;
  if (!JpegSize(data, size, &w, &h)) return "not a JPEG (no frame header)";
  if (w != width || h != height)
    return Cat("the JPEG is ", w, "x", h, ", the frame says ", width, "x", height);
  if (w <= 0 || h <= 0 || w > kMaxFrameSide || h > kMaxFrameSide) {
    return Cat(w, "x", h, " pixels: above the limit of ", kMaxFrameSide, " on a side");
  }
  return "";
}

}  // namespace viscera::client
