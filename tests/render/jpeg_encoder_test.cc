#include "render/jpeg_encoder.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "common/check.h"

namespace viscera::render {
namespace {

TEST(JpegEncoder, EncodesBgraAndDecodesToTheSameSizeAndColours) {
  cv::Mat image(48, 64, CV_8UC4, cv::Scalar(200, 100, 50, 255));  // B G R A
  image(cv::Rect(0, 0, 32, 48)).setTo(cv::Scalar(10, 20, 240, 255));
  JpegEncoder encoder(90);
  const std::vector<uint8_t>& bytes = encoder.Encode(image);
  ASSERT_GT(bytes.size(), 4u);
  EXPECT_EQ(bytes[0], 0xFF);  // JPEG SOI marker
  EXPECT_EQ(bytes[1], 0xD8);
  const cv::Mat decoded = cv::imdecode(bytes, cv::IMREAD_COLOR);
  ASSERT_EQ(decoded.rows, 48);
  ASSERT_EQ(decoded.cols, 64);
  // JPEG is lossy: flat areas away from the edge come back within a few levels.
  const cv::Vec3b left = decoded.at<cv::Vec3b>(24, 8);
  const cv::Vec3b right = decoded.at<cv::Vec3b>(24, 56);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(left[c], (cv::Vec3b(10, 20, 240))[c], 6) << "channel " << c;
    EXPECT_NEAR(right[c], (cv::Vec3b(200, 100, 50))[c], 6) << "channel " << c;
  }
}

TEST(JpegEncoder, ReusesItsBuffer) {
  const cv::Mat image(120, 160, CV_8UC3, cv::Scalar(1, 2, 3));
  JpegEncoder encoder(75);
  const uint8_t* first = encoder.Encode(image).data();
  const uint8_t* second = encoder.Encode(image).data();
  EXPECT_EQ(first, second);
}

TEST(JpegEncoder, QualityTradesSizeForFidelity) {
  cv::Mat image(64, 64, CV_8UC3);
  cv::randu(image, 0, 255);  // noise: the hardest content for JPEG
  JpegEncoder low(10);
  JpegEncoder high(95);
  EXPECT_LT(low.Encode(image).size(), high.Encode(image).size());
}

TEST(JpegEncoder, RejectsBadInput) {
  EXPECT_THROW(JpegEncoder(0), InputError);
  EXPECT_THROW(JpegEncoder(101), InputError);
  JpegEncoder encoder;
  EXPECT_THROW(encoder.Encode(cv::Mat()), InputError);
  EXPECT_THROW(encoder.Encode(cv::Mat(4, 4, CV_32FC3)), InputError);
}

}  // namespace
}  // namespace viscera::render
