#include "render/offscreen_context.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <string>

#include "common/check.h"
#include "render/gl.h"

namespace viscera::render {
namespace {

// Runs in a child process (a death-test fork) so that the environment starts as given: unset,
// a context sets LP_NUM_THREADS to 0 (rasterize in this thread); preset, it is left alone.
void ExitWithThreadsAfterAContext(const char* preset) {
  if (preset == nullptr) {
    ::unsetenv("LP_NUM_THREADS");
  } else {
    ::setenv("LP_NUM_THREADS", preset, 1);
  }
  { OffscreenContext context(16, 16); }
  const char* threads = std::getenv("LP_NUM_THREADS");
  std::exit(threads == nullptr ? 100 : std::atoi(threads));
}

TEST(OffscreenContext, GetsGl33Core) {
  OffscreenContext context(64, 48);
  std::cout << "GL_VERSION: " << context.gl_version() << "\n";
  EXPECT_TRUE(context.core_profile());
  EXPECT_GE(context.gl_version_number(), 33);
  EXPECT_NE(context.gl_version().find("Mesa"), std::string::npos) << context.gl_version();
}

TEST(OffscreenContextDeathTest, LimitsRasterizerThreadsUnlessTheEnvironmentSaysOtherwise) {
  ::testing::FLAGS_gtest_death_test_style = "threadsafe";
  EXPECT_EXIT(ExitWithThreadsAfterAContext(nullptr), ::testing::ExitedWithCode(0), "");
  EXPECT_EXIT(ExitWithThreadsAfterAContext("3"), ::testing::ExitedWithCode(3), "");
}

TEST(OffscreenContext, FrameIsBgraTopRowFirst) {
  OffscreenContext context(40, 30);
  // blue everywhere, then a red band over the top 10 rows only (scissor's y is from the
  // bottom, as everything in GL)
  glClearColor(0.0f, 0.0f, 1.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, 20, 40, 10);
  glClearColor(1.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);

  const cv::Mat frame = context.Frame();
  ASSERT_EQ(frame.rows, 30);
  ASSERT_EQ(frame.cols, 40);
  ASSERT_EQ(frame.type(), CV_8UC4);
  const cv::Vec4b top = frame.at<cv::Vec4b>(2, 5);
  const cv::Vec4b bottom = frame.at<cv::Vec4b>(27, 5);
  EXPECT_EQ(top, cv::Vec4b(0, 0, 255, 255));     // B G R A: red at the top
  EXPECT_EQ(bottom, cv::Vec4b(255, 0, 0, 255));  // blue below
}

TEST(OffscreenContext, RejectsBadSizes) {
  EXPECT_THROW(OffscreenContext(0, 10), InputError);
  EXPECT_THROW(OffscreenContext(10, 100000), InputError);
}

}  // namespace
}  // namespace viscera::render
