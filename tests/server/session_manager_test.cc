#include "server/session_manager.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <viscera_proto/jpeg_frame_t.hpp>

#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include <viscera_proto/session_reply_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "common/clock.h"
#include "tests/common/eventually.h"
#include "tests/server/manager_fixture.h"
#include "tests/session/test_scenes.h"

namespace viscera::server {
namespace {

viscera_proto::tool_pose_t GoodPose() {
  viscera_proto::tool_pose_t pose{};
  pose.header = bus::MakeHeader(7, 0);
  pose.tool = 0;
  pose.position[2] = 0.1;
  pose.orientation[0] = 1.0;
  pose.jaw = 0.5;
  return pose;
}

TEST(PoseProblem, AcceptsAGoodPoseAndNamesWhatIsWrongWithBadOnes) {
  EXPECT_EQ(PoseProblem(GoodPose(), 1), "");
  auto p = GoodPose();
  p.tool = 1;
  EXPECT_NE(PoseProblem(p, 1).find("tool 1 does not exist"), std::string::npos);
  p = GoodPose();
  p.position[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(PoseProblem(p, 1).find("position"), std::string::npos);
  p = GoodPose();
  p.position[1] = 11.0;  // beyond any operating room
  EXPECT_NE(PoseProblem(p, 1).find("position"), std::string::npos);
  p = GoodPose();
  p.orientation[3] = std::numeric_limits<double>::infinity();
  EXPECT_NE(PoseProblem(p, 1).find("orientation"), std::string::npos);
  p = GoodPose();
  p.orientation[0] = 0.1;  // norm 0.1: not a rotation
  EXPECT_NE(PoseProblem(p, 1).find("orientation"), std::string::npos);
  p = GoodPose();
  p.jaw = -0.01;
  EXPECT_NE(PoseProblem(p, 1).find("jaw"), std::string::npos);
}

TEST_F(SessionManagerTest, CreateCommandsAndDestroyWithTheToken) {
  using R = viscera_proto::session_reply_t;
  using Q = viscera_proto::session_request_t;
  auto create = Request(Q::kCreate);
  create.scene_name = "hanging";
  const R created = Ask(create);
  ASSERT_EQ(created.result, R::kOk) << created.message;
  const int64_t id = created.header.session_id;
  EXPECT_EQ(created.header.token.size(), 16u);
  EXPECT_EQ(manager_->num_sessions(), 1);
  // full: one session at most, and no peer heard yet
  const R full = Ask(create);
  EXPECT_EQ(full.result, R::kRefused);
  EXPECT_EQ(full.message, "server srv is full (1 of 1 sessions); no other server with room heard");
  // once a peer with room beats, the refusal names it (and not a full one, nor itself)
  PeerDirectory peers("srv", 3'000'000'000);
  manager_->SetPeers(&peers);
  viscera_proto::heartbeat_t hb;
  hb.header = bus::MakeHeader(0, 0);
  hb.server_id = "srv";  // our own heartbeat: not a peer
  hb.num_sessions = 0;
  hb.max_sessions = 8;
  peers.Observe(hb, MonotonicNanos());
  hb.server_id = "busy";
  hb.num_sessions = 2;
  hb.max_sessions = 2;
  peers.Observe(hb, MonotonicNanos());
  hb.server_id = "roomy";
  hb.num_sessions = 1;
  hb.max_sessions = 4;
  peers.Observe(hb, MonotonicNanos());
  EXPECT_EQ(Ask(create).message,
            "server srv is full (1 of 1 sessions); server roomy has room (1 of 4 sessions): "
            "viscera create --server roomy");

  auto pause = Request(Q::kPause, id);
  EXPECT_EQ(Ask(pause).result, R::kBadToken);  // no token
  pause.header.token = {1, 2, 3};
  pause.header.token_len = 3;
  EXPECT_EQ(Ask(pause).result, R::kBadToken);  // wrong token
  pause.header.token = created.header.token;
  pause.header.token_len = 16;
  EXPECT_EQ(Ask(pause).result, R::kOk);
  const R status = Ask(Request(Q::kStatus, id));  // no token needed
  ASSERT_EQ(status.result, R::kOk);
  ASSERT_EQ(status.num_sessions, 1);
  EXPECT_EQ(status.sessions[0].rejected, 2);
  EXPECT_EQ(Ask(Request(Q::kStatus, id + 1)).result, R::kUnknownSession);
  auto bad = Request(42, id);
  EXPECT_EQ(Ask(bad).result, R::kBadRequest);
  auto destroy = Request(Q::kDestroy, id);
  destroy.header.token = created.header.token;
  destroy.header.token_len = 16;
  const R destroyed = Ask(destroy);
  ASSERT_EQ(destroyed.result, R::kOk);
  EXPECT_EQ(destroyed.sessions[0].state, viscera_proto::session_status_t::kStopped);
  EXPECT_EQ(manager_->num_sessions(), 0);
  EXPECT_GE(manager_->rejected(), 5);
}

TEST_F(SessionManagerTest, BadScenesAndRatesAreRefusedWithTheReason) {
  using R = viscera_proto::session_reply_t;
  using Q = viscera_proto::session_request_t;
  auto r = Request(Q::kCreate);
  r.scene_name = "../etc/passwd";
  R reply = Ask(r);
  EXPECT_EQ(reply.result, R::kRefused);
  EXPECT_NE(reply.message.find("scene name"), std::string::npos) << reply.message;
  r.scene_name = "fall";
  r.rate_hz = 5000.0;
  reply = Ask(r);
  EXPECT_EQ(reply.result, R::kRefused);
  EXPECT_NE(reply.message.find("rate"), std::string::npos) << reply.message;
  r.scene_name = "";
  r.rate_hz = 0.0;
  r.scene_toml = "[intestine]\nlength = -1\n";
  EXPECT_EQ(Ask(r).result, R::kRefused);
  r.server_id = "";
  EXPECT_EQ(Ask(r).result, R::kBadRequest);  // create must name its server
  EXPECT_EQ(manager_->num_sessions(), 0);
}

TEST_F(SessionManagerTest, BadFrameSettingsAreRefusedWithTheReason) {
  using R = viscera_proto::session_reply_t;
  using Q = viscera_proto::session_request_t;
  const auto refused = [&](auto change, const char* word) {
    auto r = Request(Q::kCreate);
    r.scene_name = "hanging";
    change(&r);
    const R reply = Ask(r);
    EXPECT_EQ(reply.result, R::kRefused) << word;
    EXPECT_NE(reply.message.find(word), std::string::npos) << reply.message;
  };
  refused([](Q* r) { r->skin = "marble"; }, "skin");
  refused([](Q* r) { r->jpeg_quality = 101; }, "quality");
  refused([](Q* r) { r->frame_rate_hz = 1000.0; }, "frame rate");
  refused([](Q* r) { r->frame_rate_hz = std::nan(""); }, "frame rate");
  refused([](Q* r) { r->frame_width = 8; }, "frame size");
  refused([](Q* r) { r->frame_height = 5000; }, "frame size");
  EXPECT_EQ(manager_->num_sessions(), 0);
}

// A session's render thread: real OSMesa pixels, real JPEG bytes, on the frame channel.
TEST_F(SessionManagerTest, FramesOfTheRequestedSizeFollowTheMechanics) {
  using R = viscera_proto::session_reply_t;
  using Q = viscera_proto::session_request_t;
  std::vector<viscera_proto::jpeg_frame_t> frames;
  auto create = Request(Q::kCreate);
  create.scene_name = "hanging";
  create.frame_width = 160;
  create.frame_height = 120;
  create.frame_rate_hz = 20.0;
  create.skin = "convolution";
  const R created = Ask(create);
  ASSERT_EQ(created.result, R::kOk) << created.message;
  const int64_t id = created.header.session_id;
  bus_.Subscribe<viscera_proto::jpeg_frame_t>(
      bus::SessionChannel(bus::kFramePrefix, id),
      [&](const viscera_proto::jpeg_frame_t& f, int64_t) { frames.push_back(f); });
  // the render thread runs SCHED_IDLE: on a busy machine its first frames may take a while;
  // a viewer renews the frame lease meanwhile (no token needed)
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  auto next_watch = std::chrono::steady_clock::now();
  while (frames.size() < 8 && std::chrono::steady_clock::now() < give_up) {
    if (std::chrono::steady_clock::now() >= next_watch) {
      ASSERT_EQ(Ask(Request(Q::kWatchFrames, id)).result, R::kOk);
      next_watch += std::chrono::milliseconds(500);
    }
    bus_.Pump(20);
  }

  ASSERT_GE(frames.size(), 8u);
  for (size_t i = 0; i < frames.size(); ++i) {
    const auto& f = frames[i];
    EXPECT_EQ(f.header.session_id, id);
    EXPECT_EQ(f.width, 160);
    EXPECT_EQ(f.height, 120);
    EXPECT_LE(f.snapshot_utime, f.header.utime);
    const cv::Mat image = cv::imdecode(f.data, cv::IMREAD_COLOR);
    ASSERT_EQ(image.cols, 160);
    ASSERT_EQ(image.rows, 120);
    cv::Scalar mean, dev;
    cv::meanStdDev(image, mean, dev);
    EXPECT_GT(dev[2], 5.0) << "frame " << i << " is uniform";
    if (i > 0) {
      EXPECT_EQ(f.header.seq, frames[i - 1].header.seq + 1);  // in-process: nothing lost
      EXPECT_GE(f.step, frames[i - 1].step);  // a late frame may show the same step again
      EXPECT_GE(f.sim_time, frames[i - 1].sim_time);
    }
  }
  EXPECT_GT(frames.back().step, frames.front().step);  // the stream follows the mechanics
  const R status = Ask(Request(Q::kStatus, id));
  ASSERT_EQ(status.num_sessions, 1);
  const auto& s = status.sessions[0];
  EXPECT_EQ(s.skin, "convolution");
  EXPECT_EQ(s.frame_width, 160);
  EXPECT_DOUBLE_EQ(s.frame_rate_hz, 20.0);
  // the thread reports after it publishes, and a status never waits for its report
  EXPECT_GE(s.frames + 2, static_cast<int64_t>(frames.size()));
  EXPECT_GT(s.frames, 0);
  EXPECT_GT(s.render_ms, 0.0f);
  EXPECT_GT(s.encode_ms, 0.0f);
  EXPECT_GT(s.frame_bytes, 0);

  // a camera the renderer could not use is refused with the reason; a good one is taken
  auto camera = Request(Q::kCamera, id);
  camera.header.token = created.header.token;
  camera.header.token_len = 16;
  camera.camera_eye[2] = 0.5;  // looking straight down, with up along the view
  camera.camera_up[2] = 1.0;
  camera.camera_fov_deg = 60.0;
  R reply = Ask(camera);
  EXPECT_EQ(reply.result, R::kRefused);
  EXPECT_NE(reply.message.find("along the view"), std::string::npos) << reply.message;
  camera.camera_up[2] = 0.0;
  camera.camera_up[1] = 1.0;
  EXPECT_EQ(Ask(camera).result, R::kOk);
}

}  // namespace
// The frame lease: no viewer, no frame drawn (the status's frame counter stays flat); frames
// while a viewer renews the lease; and they stop within the lease once it stops renewing. The
// control: a server without a frame lease draws frames nobody asked for.
TEST_F(SessionManagerTest, FramesAreDrawnOnlyWhileAViewerRenewsTheFrameLease) {
  using R = viscera_proto::session_reply_t;
  using Q = viscera_proto::session_request_t;
  using Clock = std::chrono::steady_clock;
  const auto frames_of = [&](double lease_s) -> std::pair<int64_t, int64_t> {
    config_.frame_lease_s = lease_s;
    manager_ = std::make_unique<SessionManager>(config_, &bus_, &bus_);
    auto create = Request(Q::kCreate);
    create.scene_name = "hanging";
    create.frame_width = 160;
    create.frame_height = 120;
    create.frame_rate_hz = 20.0;
    const R created = Ask(create);
    EXPECT_EQ(created.result, R::kOk) << created.message;
    const int64_t id = created.header.session_id;
    int64_t received = 0;
    const auto subscription = bus_.Subscribe<viscera_proto::jpeg_frame_t>(
        bus::SessionChannel(bus::kFramePrefix, id),
        [&](const viscera_proto::jpeg_frame_t&, int64_t) { ++received; });
    const auto pump_for = [&](double seconds) {
      const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                            std::chrono::duration<double>(seconds));
      while (Clock::now() < until) bus_.Pump(20);
    };
    pump_for(2.0);  // a session of 20 Hz frames that nobody watches
    const R unwatched = Ask(Request(Q::kStatus, id));
    bus_.Unsubscribe(subscription);
    Ask([&] {
      auto r = Request(Q::kDestroy, id);
      r.header.token = created.header.token;
      r.header.token_len = 16;
      return r;
    }());
    return {unwatched.sessions[0].frames, received};
  };
  const auto [drawn_with_lease, received_with_lease] = frames_of(1.0);
  EXPECT_EQ(drawn_with_lease, 0);
  EXPECT_EQ(received_with_lease, 0);
  const auto [drawn_without_lease, received_without_lease] = frames_of(0.0);  // the control
  EXPECT_GT(drawn_without_lease, 0);
  EXPECT_GT(received_without_lease, 0);

  // watched, then left: frames while the lease is renewed, none from the lease (1 s) and a slow
  // frame (1.5 s on a busy machine) after the last renewal
  config_.frame_lease_s = 1.0;
  manager_ = std::make_unique<SessionManager>(config_, &bus_, &bus_);
  auto create = Request(Q::kCreate);
  create.scene_name = "hanging";
  create.frame_width = 160;
  create.frame_height = 120;
  create.frame_rate_hz = 20.0;
  const R created = Ask(create);
  ASSERT_EQ(created.result, R::kOk) << created.message;
  const int64_t id = created.header.session_id;
  int64_t received = 0;
  bus_.Subscribe<viscera_proto::jpeg_frame_t>(
      bus::SessionChannel(bus::kFramePrefix, id),
      [&](const viscera_proto::jpeg_frame_t&, int64_t) { ++received; });
  const auto give_up = Clock::now() + std::chrono::seconds(30);
  while (received < 5 && Clock::now() < give_up) {  // SCHED_IDLE: slow on a busy machine
    ASSERT_EQ(Ask(Request(Q::kWatchFrames, id)).result, R::kOk);
    const auto until = Clock::now() + std::chrono::milliseconds(300);
    while (Clock::now() < until) bus_.Pump(20);
  }
  ASSERT_GE(received, 5);
  const auto left = Clock::now();  // the viewer vanishes
  while (Clock::now() < left + std::chrono::milliseconds(2500)) bus_.Pump(20);
  const int64_t after_lease = Ask(Request(Q::kStatus, id)).sessions[0].frames;
  const int64_t received_after_lease = received;
  while (Clock::now() < left + std::chrono::milliseconds(4500)) bus_.Pump(20);
  EXPECT_EQ(Ask(Request(Q::kStatus, id)).sessions[0].frames, after_lease);
  EXPECT_EQ(received, received_after_lease);
}

}  // namespace viscera::server

namespace viscera::server {
namespace {

// Admission charges every session its steps and only the sessions that stream frames their
// frames (at their own rate): a server whose budget holds one frame stream holds several
// sessions without frames. The figures are a made-up estimate, so the test is not timed.
TEST_F(SessionManagerTest, AdmissionChargesFramesOnlyToSessionsThatStreamThem) {
  using R = viscera_proto::session_reply_t;
  using Q = viscera_proto::session_request_t;
  ServerConfig c = config_;
  c.frame_width = 64;  // frames for real, but small
  c.frame_height = 48;
  Restart(c);
  CapacityEstimate e;
  e.scene = "hanging";
  e.cores = 1;  // budget 0.7 core
  e.rate_hz = 100.0;
  e.step_cpu_us = 2000.0;
  e.session_cores = 0.2;
  e.frame_rate_hz = 25.0;
  e.frame_cpu_ms = 20.0;  // a 25 Hz stream: 0.5 core
  e.frame_width = 64;
  e.frame_height = 48;
  e.max_sessions = SessionsThatFit(e.cores, e.session_cores);
  ASSERT_EQ(e.max_sessions, 3);
  EXPECT_DOUBLE_EQ(e.SessionCores(-1.0, 64, 48), 0.2);
  EXPECT_DOUBLE_EQ(e.SessionCores(25.0, 64, 48), 0.7);
  EXPECT_DOUBLE_EQ(e.SessionCores(10.0, 128, 96), 0.2 + 0.8);  // its own rate and size
  EXPECT_NE(e.Describe().find("max 3 sessions without frames"), std::string::npos) << e.Describe();
  EXPECT_NE(e.Describe().find("so 1 with frames"), std::string::npos) << e.Describe();
  manager_->SetCapacity(e);

  const auto create = [&](double frame_rate_hz) {
    auto r = Request(Q::kCreate);
    r.scene_name = "hanging";
    r.frame_rate_hz = frame_rate_hz;  // 0: the server's default (25 Hz), < 0: none
    return Ask(r);
  };
  const auto destroy = [&](const R& created) {
    auto r = Request(Q::kDestroy, created.header.session_id);
    r.header.token = created.header.token;
    r.header.token_len = static_cast<int32_t>(created.header.token.size());
    EXPECT_EQ(Ask(r).result, R::kOk);
  };
  const R a = create(-1.0), b = create(-1.0);
  ASSERT_EQ(a.result, R::kOk) << a.message;
  ASSERT_EQ(b.result, R::kOk) << b.message;
  const R framed = create(0.0);  // 0.4 + 0.7 > 0.7
  EXPECT_EQ(framed.result, R::kRefused);
  EXPECT_NE(framed.message.find("it would cost 0.7 core (25 Hz frames included)"),
            std::string::npos)
      << framed.message;
  EXPECT_NE(framed.message.find("no frames"), std::string::npos) << framed.message;
  const R third = create(-1.0);  // 0.6: fits
  ASSERT_EQ(third.result, R::kOk) << third.message;
  EXPECT_EQ(create(-1.0).message,
            "server srv is full (3 of 3 sessions); no other server with room heard");
  destroy(a);
  destroy(b);
  EXPECT_EQ(create(0.0).result, R::kRefused);  // 0.2 + 0.7 > 0.7
  destroy(third);
  // an idle server takes any one session, even one beyond its budget (0.2 + 40 x 20 ms)
  const R alone = create(40.0);
  EXPECT_EQ(alone.result, R::kOk) << alone.message;
  EXPECT_EQ(manager_->num_sessions(), 1);
}

}  // namespace
}  // namespace viscera::server

namespace viscera::server {
namespace {

// On a bus shared by several servers each hears the others' poses and requests: they are
// counted apart (not_ours), and rejected keeps meaning invalid or hostile traffic.
TEST_F(SessionManagerTest, TrafficForOtherServersSessionsIsNotRejected) {
  using R = viscera_proto::session_reply_t;
  using Q = viscera_proto::session_request_t;
  viscera_proto::tool_pose_t pose{};
  pose.header = bus::MakeHeader(777, 1);
  pose.orientation[0] = 1.0;
  const std::string channel = bus::SessionChannel(bus::kPosePrefix, 777);
  manager_->OnPose(pose, bus::MessageInfo{&channel, 0, 0});
  EXPECT_EQ(Ask(Request(Q::kStatus, 777)).result, R::kUnknownSession);
  EXPECT_EQ(manager_->not_ours(), 2);
  EXPECT_EQ(manager_->rejected(), 0);
  // a hostile message still is rejected: garbage on the pose channel, a bad request
  const std::vector<uint8_t> garbage(40, 0xab);
  manager_->OnDrop(channel, bus::DropReason::kMalformed, garbage.data(),
                   static_cast<int>(garbage.size()));
  EXPECT_EQ(Ask(Request(42)).result, R::kBadRequest);
  EXPECT_EQ(manager_->rejected(), 2);
  EXPECT_EQ(manager_->not_ours(), 2);
}

// The heartbeat's unconverged_solves: the sessions' counts summed, those running (as of their
// latest status) and those ended, so that it never goes back when a session ends.
TEST_F(SessionManagerTest, UnconvergedSolvesAreSummedOverRunningAndEndedSessions) {
  using R = viscera_proto::session_reply_t;
  using Q = viscera_proto::session_request_t;
  const auto pump = [&] {
    bus_.Drain();
    manager_->Poll();
  };
  int64_t ended = 0;
  for (int round = 0; round < 2; ++round) {
    auto create = Request(Q::kCreate);
    create.scene_toml = session::testing::UnconvergedSceneToml();
    const R created = Ask(create);
    ASSERT_EQ(created.result, R::kOk) << created.message;
    const int64_t id = created.header.session_id;
    int64_t running = 0;
    ASSERT_TRUE(viscera::testing::Eventually(
        [&] {
          const R status = Ask(Request(Q::kStatus, id));
          running = status.num_sessions == 1 ? status.sessions[0].unconverged_solves : 0;
          return running > 0;
        },
        30.0, pump));
    EXPECT_GE(manager_->unconverged_solves(),
              ended + running);  // its status may have moved on since
    auto destroy = Request(Q::kDestroy, id);
    destroy.header.token = created.header.token;
    destroy.header.token_len = 16;
    const R destroyed = Ask(destroy);
    ASSERT_EQ(destroyed.result, R::kOk);
    ASSERT_EQ(destroyed.num_sessions, 1);
    EXPECT_GE(destroyed.sessions[0].unconverged_solves, running);  // the final status: never less
    ended += destroyed.sessions[0].unconverged_solves;
    EXPECT_EQ(manager_->num_sessions(), 0);
    EXPECT_EQ(manager_->unconverged_solves(), ended) << "round " << round;
  }
}

}  // namespace
}  // namespace viscera::server
