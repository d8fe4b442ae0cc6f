// End to end: a session's frame stream from the real viscerad to the real viscera over real
// UDP multicast, inside a private loopback-only network namespace (tests/e2e/in_netns.sh).
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "tests/common/eventually.h"
#include "tests/e2e/e2e_harness.h"

namespace viscera::e2e {
namespace {

using nlohmann::json;
using viscera::testing::Eventually;

json Status(const std::string& dir, const std::string& id) {
  const CliResult r = Viscera(dir, "status " + id + " --json");
  EXPECT_EQ(r.rc, 0) << r.out;
  return r.rc == 0 ? r.json() : json();
}

// Polls until `done` holds for the session's status (30 s at most, then the test fails).
json StatusWhen(const std::string& dir, const std::string& id,
                const std::function<bool(const json&)>& done) {
  json s;
  EXPECT_TRUE(Eventually(
      [&] {
        s = Status(dir, id);
        return !s.is_null() && done(s);
      },
      30.0, [] { Sleep(0.05); }))
      << "last status: " << s.dump();
  return s;
}

cv::Mat Decode(const std::string& path) { return cv::imread(path, cv::IMREAD_COLOR); }

double MeanAbsDifference(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  return cv::mean(d)[0] + cv::mean(d)[1] + cv::mean(d)[2];
}

// Frames arrive, decode to the requested size and show the tube moving; every frame the
// client counted is one the server sent. How fast, how late and how many are lost on this
// machine is bench/frames_bench.sh's to measure (docs/server-benchmarks.md, "Frame streams").
TEST(FramesE2E, FramesArriveDecodeAndAreAccountedFor) {
  const std::string dir = ScratchDir();
  Daemon daemon("e2e-frames", {"--adaptive-frames", "off"}, dir);
  // a tube that swings for seconds: the frames show it moving whenever they are watched
  const int64_t id = Create(dir, "--scene-file " + std::string(VISCERA_SOURCE_DIR) +
                                     "/tests/e2e/scenes/swing.toml --width 640 --height 480 "
                                     "--frame-rate 25")["session"];
  ASSERT_GT(id, 0);
  const std::string sid = std::to_string(id);
  // nobody watches yet: the render thread draws nothing (the frame lease; viscera frames renews it)
  const json unwatched =
      StatusWhen(dir, sid, [](const json& s) { return s["steps"].get<int64_t>() > 100; });
  EXPECT_EQ(unwatched["frames"]["sent"].get<int64_t>(), 0) << unwatched.dump();

  // a count, not a duration: however slowly a loaded machine renders (the renderer runs
  // SCHED_IDLE and yields to everything), the test waits for these frames
  const CliResult frames =
      Viscera(dir, "frames " + sid + " --out " + dir + "/frames --count 12 --timeout 60 --json");
  ASSERT_EQ(frames.rc, 0) << frames.out;
  const json f = frames.json();
  // the status board publishes the server's counts a little later than the frames go out
  const json after = StatusWhen(dir, sid, [&](const json& s) {
    return s["frames"]["sent"].get<int64_t>() >=
           f["frames"].get<int64_t>() + f["lost"].get<int64_t>();
  });
  // liveness, and exact bookkeeping: what the client received or counted lost, the server sent
  EXPECT_EQ(f["frames"].get<int64_t>(), 12) << f.dump();
  EXPECT_LE(f["frames"].get<int64_t>() + f["lost"].get<int64_t>(),
            after["frames"]["sent"].get<int64_t>())
      << f.dump();
  EXPECT_LE(f["server_dropped"].get<int64_t>(), after["frames"]["dropped"].get<int64_t>())
      << f.dump();
  EXPECT_GE(f["lost"].get<int64_t>(), 0);
  EXPECT_GT(f["rate_hz"].get<double>(), 0.0) << f.dump();
  EXPECT_GT(f["age_p50_ms"].get<double>(), 0.0) << f.dump();

  const int64_t n = f["frames"];
  int64_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir + "/frames"))
    files += entry.is_regular_file();
  EXPECT_EQ(files, n);
  const cv::Mat first = Decode(dir + "/frames/frame_000000.jpg");
  char last_name[64];
  std::snprintf(last_name, sizeof(last_name), "/frames/frame_%06lld.jpg",
                static_cast<long long>(n - 1));
  const cv::Mat last = Decode(dir + last_name);
  ASSERT_EQ(first.cols, 640);
  ASSERT_EQ(first.rows, 480);
  ASSERT_EQ(last.size(), first.size());
  cv::Scalar mean, dev;
  cv::meanStdDev(first, mean, dev);
  EXPECT_GT(dev[2], 10.0) << "the first frame is uniform";
  EXPECT_GT(MeanAbsDifference(first, last), 1.0) << "the swinging tube did not move over 12 frames";

  const json s = Status(dir, sid);
  EXPECT_EQ(s["state"], "running");
  EXPECT_GT(s["frames"]["rate_hz"].get<double>(), 0.0) << s.dump();
  EXPECT_EQ(s["frames"]["skin"], "parametric");  // the server default
  EXPECT_EQ(s["frames"]["size"], "640x480");
  EXPECT_GT(s["frames"]["render_ms"].get<double>(), 0.0);
  EXPECT_GT(s["frames"]["encode_ms"].get<double>(), 0.0);
  EXPECT_EQ(daemon.Stop(), 0);
}

// The client's camera moves the picture; a video of the stream plays back at its size.
TEST(FramesE2E, TheCameraMovesThePictureAndARecordingPlaysBack) {
  const std::string dir = ScratchDir();
  Daemon daemon("e2e-video", {"--adaptive-frames", "off"}, dir);
  const std::string id =
      std::to_string(Create(dir, "hanging --width 320 --height 240")["session"].get<int64_t>());
  ASSERT_EQ(Viscera(dir, "pause " + id).rc, 0);  // a still tube: only the camera changes
  StatusWhen(dir, id, [](const json& s) { return s["state"] == "paused"; });
  // two frames in a row alike: the picture of the paused tube is settled
  cv::Mat a;
  int fetched = 0;
  ASSERT_TRUE(Eventually(
      [&] {
        const std::string out = dir + "/a" + std::to_string(fetched++);
        if (Viscera(dir, "frames " + id + " --out " + out + " --count 1 --timeout 60").rc != 0)
          return false;
        const cv::Mat next = Decode(out + "/frame_000000.jpg");
        const bool settled =
            !a.empty() && next.size() == a.size() && MeanAbsDifference(a, next) < 1.0;
        a = next;
        return settled;
      },
      30.0));
  ASSERT_EQ(a.cols, 320);
  ASSERT_EQ(Viscera(dir, "camera " + id + " --eye 0.6 0.6 0.2 --target 0 0 0").rc, 0);
  // the new view shows up in a later frame
  double moved = 0.0;
  EXPECT_TRUE(Eventually(
      [&] {
        const std::string out = dir + "/b" + std::to_string(fetched++);
        if (Viscera(dir, "frames " + id + " --out " + out + " --count 1 --timeout 60").rc != 0)
          return false;
        const cv::Mat b = Decode(out + "/frame_000000.jpg");
        moved = b.size() == a.size() ? MeanAbsDifference(a, b) : 0.0;
        return moved > 5.0;
      },
      30.0))
      << "the camera did not move the picture (difference " << moved << ")";

  ASSERT_EQ(Viscera(dir, "resume " + id).rc, 0);
  const CliResult record =
      Viscera(dir, "record " + id + " --out " + dir + "/clip.mp4 --count 25 --timeout 60 --json");
  ASSERT_EQ(record.rc, 0) << record.out;
  cv::VideoCapture video(dir + "/clip.mp4");
  ASSERT_TRUE(video.isOpened());
  int decoded = 0;
  for (cv::Mat frame; video.read(frame); ++decoded) {
    ASSERT_EQ(frame.cols, 320);
    ASSERT_EQ(frame.rows, 240);
  }
  // 25 frames, plus the picture repeated for each tick without a frame (lost or dropped by
  // the renderer, at most a second's worth per gap): an exact bound, whatever the load
  const json r = record.json();
  EXPECT_EQ(r["frames"], 25);
  EXPECT_GE(decoded, 25);
  EXPECT_LE(decoded, 25 + r["lost"].get<int64_t>() + r["server_dropped"].get<int64_t>())
      << r.dump();
  EXPECT_EQ(daemon.Stop(), 0);
}

// A session without frames: no render thread, and the client says so instead of hanging.
TEST(FramesE2E, ASessionWithoutFramesSaysSo) {
  const std::string dir = ScratchDir();
  Daemon daemon("e2e-noframes", {}, dir);
  const std::string id =
      std::to_string(Create(dir, "hanging --frame-rate -1")["session"].get<int64_t>());
  const CliResult none = Viscera(dir, "frames " + id + " --out " + dir + "/none --count 1");
  EXPECT_EQ(none.rc, 2);
  const CliResult status = Viscera(dir, "status " + id + " --json");
  EXPECT_EQ(status.json()["frames"]["sent"], 0);
  EXPECT_EQ(Viscera(dir, "create hanging --skin marble --timeout 30").rc,
            4);  // refused with the reason
  EXPECT_EQ(daemon.Stop(), 0);
}

}  // namespace
}  // namespace viscera::e2e
