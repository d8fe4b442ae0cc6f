// Running the bowel in the server's frames: a session's grasper shuts its jaws on a tube (a pinch,
// scored live), lets go and draws back; the frame the session's render thread then sends shows
// that segment in the damage colour, where the camera sees it and nowhere else (the decoded
// JPEG's pixels, against the segment's ends projected through the same camera). The exposure
// watcher hands the session the frames' camera: running the bowel's camera coverage counts what
// it sees.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <viscera_proto/jpeg_frame_t.hpp>

#include "bus/channels.h"
#include "render/laparoscope.h"
#include "scene/scene.h"
#include "server/exposure_watcher.h"
#include "server/frame_streamer.h"
#include "tests/common/eventually.h"
#include "tests/mechanics/table_scene.h"
#include "tests/session/script_driver.h"

namespace viscera::server {
namespace {

using viscera::testing::Eventually;

constexpr int64_t kId = 9;
constexpr int kWidth = 320, kHeight = 240;

// The table's 60 cm tube (tests/mechanics/table_scene.h) scored as running the bowel: 12
// segments of 5 cm; every segment in the camera's view within 60 cm counts as inspected. The
// grasper grips with 20 N shut, past the 10.3 N pinch force.
std::string RunningTableScene() {
  std::string toml = viscera::testing::kTableScene;
  const std::string force = "max_force = 5.0";
  toml.replace(toml.find(force), force.size(), "max_force = 25.0\njaw_force = 20.0");
  return toml + "[running]\nsegment = 0.05\ncamera_range = 0.6\n";
}

// Down on the middle of segment 6 (30-35 cm), shut the jaws, open them and draw back up and aside,
// out of the camera's way.
constexpr const char* kPinch = R"(t,tool,x,y,z,qw,qx,qy,qz,jaw
0,grasper,0.325,0,0.06,1,0,0,0,1
0.2,grasper,0.325,0,0.0275,1,0,0,0,1
0.7,grasper,0.325,0,0.0275,1,0,0,0,1
0.8,grasper,0.325,0,0.0275,1,0,0,0,0
1.1,grasper,0.325,0,0.0275,1,0,0,0,0
1.2,grasper,0.325,0,0.0275,1,0,0,0,1
1.6,grasper,0.3,-0.1,0.2,1,0,0,0,1
)";

// The camera straight above the tube's middle, +x to the right, +y up the frame.
session::CameraPose Camera() {
  session::CameraPose pose;
  pose.eye = Vec3(0.3, 0.0, 0.3);
  pose.target = Vec3(0.3, 0.0, 0.0125);
  pose.up = Vec3::UnitY();
  pose.fov_deg = 55.0;  // the frame 40 cm wide on the tube: its edges half a segment from a middle
  pose.set_by_client = true;
  return pose;
}

struct DamageColumns {
  long pixels = 0;
  int first = -1, last = -1;
};

// The columns of the frame's pixels in the damage colour (a saturated blue-violet no tissue,
// instrument or organ has: tests/render/damage_colour_test.cc).
DamageColumns DamageIn(const viscera_proto::jpeg_frame_t& frame) {
  const cv::Mat image = cv::imdecode(frame.data, cv::IMREAD_COLOR);
  EXPECT_EQ(image.cols, kWidth);
  DamageColumns c;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b bgr = image.at<cv::Vec3b>(y, x);
      if (bgr[0] > 140 && bgr[2] < 120 && bgr[1] < 90) {
        ++c.pixels;
        c.first = c.first < 0 ? x : std::min(c.first, x);
        c.last = std::max(c.last, x);
      }
    }
  }
  return c;
}

TEST(RunningFrames, ThePinchedSegmentIsDrawnInTheDamageColourWhereItLies) {
  const scene::Scene scene = scene::ParseScene(RunningTableScene(), "running table");
  auto model = std::make_shared<const mechanics::Model>(scene.model);
  bus::LcmBus bus("memq://");
  std::vector<viscera_proto::jpeg_frame_t> frames;
  bus.Subscribe<viscera_proto::jpeg_frame_t>(
      bus::SessionChannel(bus::kFramePrefix, kId),
      [&](const viscera_proto::jpeg_frame_t& f, int64_t) { frames.push_back(f); });
  session::SessionConfig config;
  config.id = kId;
  config.server_id = "test";
  config.scene = "running table";
  config.skeleton_rate_hz = 0.0;
  config.snapshot_rate_hz = model->params().rate_hz;  // as the server sets it while frames stream
  session::Session session(config, model, &bus, nullptr);
  session.SetCamera(Camera());
  FrameStreamConfig stream;
  stream.rate_hz = 10.0;
  stream.adaptive = false;
  stream.options.width = kWidth;
  stream.options.height = kHeight;
  stream.options.jpeg_quality = 95;
  FrameStreamer streamer(&session, &bus, stream);
  ExposureWatcher watcher(&session, ExposureWatchConfig{kWidth, kHeight});
  session::testing::ScriptDriver driver(&session, script::ToolScript::Parse(kPinch, "pinch"));
  session.Start();
  streamer.Start();
  watcher.Start();
  // a frame of the tube after the grasper drew back (the render thread runs SCHED_IDLE: on a
  // busy machine its frames come late)
  ASSERT_TRUE(Eventually([&] { return !frames.empty() && frames.back().sim_time >= 1.8; }, 60.0,
                         [&] {
                           driver.Post();
                           bus.Pump(2);
                         }));
  watcher.Stop();
  streamer.Stop();
  session.Stop();
  const assessment::Report report = session.Assessment();

  // the pinch, scored live: one event, on the segment the jaws shut on
  ASSERT_TRUE(report.has_running);
  ASSERT_EQ(report.running.events.size(), 1u) << assessment::FormatRunning(report.running);
  EXPECT_EQ(report.running.events[0].kind, "pinch");
  const int segment = report.running.events[0].segment;
  EXPECT_EQ(segment, 6);
  EXPECT_EQ(report.running.damaged, std::vector<int>{segment});
  // the camera the frames are drawn from inspects every segment whose middle it sees (within
  // 60 cm): all but the two at each end, out of the frame (without it, the jaws' one)
  EXPECT_EQ(report.running.missed, (std::vector<int>{0, 1, 10, 11}))
      << "the frames' camera did not reach the score";

  // the last frame: the damage colour over the segment's columns and nowhere else
  const DamageColumns c = DamageIn(frames.back());
  ASSERT_GT(c.pixels, 200) << "no damage colour in the frame";
  const render::CameraMatrices camera =
      render::LookAtLaparoscope(Camera().eye, Camera().target, Camera().up, Camera().fov_deg)
          .Matrices(kWidth, kHeight);
  const auto column = [&](double x) {  // the tube's top at x (m) along it
    return render::Project(camera, kWidth, kHeight, Eigen::Vector3f(x, 0.0f, 0.025f)).pixel.x();
  };
  const double from = column(0.05 * segment), to = column(0.05 * (segment + 1));
  ASSERT_GT(to - from, 30.0);
  // within 4 px (6 mm along the tube: a skin triangle's share and the tube drawn in by the grasp)
  EXPECT_NEAR(c.first, from, 4.0);
  EXPECT_NEAR(c.last + 1, to, 4.0);
}

}  // namespace
}  // namespace viscera::server
