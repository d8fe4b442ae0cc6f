#pragma once
/// Reads a JPEG's size from its frame header, before anything decodes it: a 1 KB JPEG that
/// claims 30000 x 30000 pixels made the decoder allocate 2.65 GB.
#include <cstddef>
#include <cstdint>
#include <string>

namespace viscera::client {

/// Largest side a client decodes (pixels): the servers' frames are at most 4096 on a side.
inline constexpr int kMaxFrameSide = 4096;

/// The width and height in the first start-of-frame marker of `data` (SOF0..SOF15), walking
/// the marker segments from SOI. @return false for anything that is not such a JPEG (no SOI,
/// a truncated segment, no SOF before the scan).
bool JpegSize(const uint8_t* data, size_t size, int* width, int* height);

/// Why the frame `data` claiming `width` x `height` must not be decoded ("" to decode it):
/// not a JPEG, a size other than the one claimed, or a side above kMaxFrameSide.
std::string JpegProblem(const uint8_t* data, size_t size, int width, int height);

}  // namespace viscera::client
