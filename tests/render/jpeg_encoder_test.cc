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

// libjpeg-turbo fed BGRA (or BGR, or grey) rows as they are gives the bytes of OpenCV's writer,
// which copies each row to BGR first: the same picture. Control: another quality differs.
TEST(JpegEncoder, GivesTheBytesOfOpenCvsWriter) {
  cv::Mat bgra(120, 160, CV_8UC4);
  cv::randu(bgra, 0, 255);
  bgra(cv::Rect(20, 10, 100, 60)).setTo(cv::Scalar(60, 90, 220, 255));
  cv::Mat bgr, grey;
  cv::extractChannel(bgra, grey, 1);
  cv::Mat channels[3];
  for (int c = 0; c < 3; ++c) cv::extractChannel(bgra, channels[c], c);
  cv::merge(channels, 3, bgr);
  for (const cv::Mat& image : {bgra, bgr, grey}) {
    SCOPED_TRACE(image.channels());
    std::vector<uint8_t> opencv;
    ASSERT_TRUE(cv::imencode(".jpg", image, opencv, {cv::IMWRITE_JPEG_QUALITY, 85}));
    JpegEncoder encoder(85);
    EXPECT_EQ(encoder.Encode(image), opencv);
    // control: the comparison sees a change of quality
    EXPECT_NE(JpegEncoder(84).Encode(image), opencv);
  }
  // a view into a larger image (its rows are strided) encodes as its copy
  const cv::Mat view = bgra(cv::Rect(8, 4, 96, 64));
  JpegEncoder encoder(85);
  const std::vector<uint8_t> strided = encoder.Encode(view);
  EXPECT_EQ(strided, encoder.Encode(view.clone()));
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
