// A client reads a frame's JPEG header before it decodes anything (docs/security.md): a 1 KB
// JPEG claiming 30000 x 30000 pixels made `viscera record` allocate 2.65 GB.
#include "client/jpeg_header.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <vector>

namespace viscera::client {
namespace {

std::vector<uint8_t> Encoded(int width, int height) {
  std::vector<uint8_t> jpeg;
  EXPECT_TRUE(cv::imencode(".jpg", cv::Mat(height, width, CV_8UC3, cv::Scalar(40, 80, 160)), jpeg));
  return jpeg;
}

// The size field of a real JPEG's frame header, set to `width` x `height`.
std::vector<uint8_t> Claiming(std::vector<uint8_t> jpeg, int width, int height) {
  for (size_t i = 2; i + 9 < jpeg.size(); ++i) {
    if (jpeg[i] == 0xFF && jpeg[i + 1] == 0xC0) {
      jpeg[i + 5] = static_cast<uint8_t>(height >> 8);
      jpeg[i + 6] = static_cast<uint8_t>(height);
      jpeg[i + 7] = static_cast<uint8_t>(width >> 8);
      jpeg[i + 8] = static_cast<uint8_t>(width);
      return jpeg;
    }
  }
  ADD_FAILURE() << "no SOF0";
  return jpeg;
}

TEST(JpegHeader, ReadsTheSizeOfARealJpeg) {
  const std::vector<uint8_t> jpeg = Encoded(160, 120);
  int w = 0, h = 0;
  ASSERT_TRUE(JpegSize(jpeg.data(), jpeg.size(), &w, &h));
  EXPECT_EQ(w, 160);
  EXPECT_EQ(h, 120);
  EXPECT_EQ(JpegProblem(jpeg.data(), jpeg.size(), 160, 120), "");
}

TEST(JpegHeader, AHugeClaimIsRefusedBeforeDecoding) {
  const std::vector<uint8_t> huge = Claiming(Encoded(16, 16), 30000, 30000);
  EXPECT_LT(huge.size(), 2000u);
  EXPECT_EQ(JpegProblem(huge.data(), huge.size(), 30000, 30000),
            "30000x30000 pixels: above the limit of 4096 on a side");
  EXPECT_EQ(JpegProblem(huge.data(), huge.size(), 16, 16),
            "the JPEG is 30000x30000, the frame says 16x16");
}

TEST(JpegHeader, AnythingElseIsNotAJpeg) {
  const std::vector<uint8_t> jpeg = Encoded(32, 24);
  int w = 0, h = 0;
  EXPECT_FALSE(JpegSize(jpeg.data(), 0, &w, &h));
  EXPECT_FALSE(JpegSize(jpeg.data(), 20, &w, &h));  // cut before the frame header
  const std::vector<uint8_t> text = {'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd'};
  EXPECT_FALSE(JpegSize(text.data(), text.size(), &w, &h));
  std::vector<uint8_t> lying = {0xFF, 0xD8, 0xFF,
                                0xE0, 0xFF, 0xFF};  // a segment longer than the data
  EXPECT_FALSE(JpegSize(lying.data(), lying.size(), &w, &h));
  EXPECT_EQ(JpegProblem(text.data(), text.size(), 32, 24), "not a JPEG (no frame header)");
}

}  // namespace
}  // namespace viscera::client
