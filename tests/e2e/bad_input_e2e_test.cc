// End to end, hostile datagrams: the real viscerad and the real viscera over real UDP
// multicast, inside a private loopback-only network namespace (tests/e2e/in_netns.sh runs every
// test).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <viscera_proto/heartbeat_t.hpp>
#include <viscera_proto/session_reply_t.hpp>
#include <viscera_proto/session_request_t.hpp>
#include <viscera_proto/tool_pose_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/lcm_bus.h"
#include "client/token_store.h"
#include "session/replay.h"
#include "tests/common/eventually.h"
#include "tests/e2e/e2e_harness.h"
#include "tests/e2e/session_driving.h"

namespace viscera::e2e {
namespace {

using nlohmann::json;
using viscera::testing::Eventually;

// Every kind of bad datagram, one at a time, to a session whose scene has a tool (so that the
// value checks are reached, not hidden behind "no such tool"): each is dropped, counted
// exactly once against the right session, and named in last_error. The flood is its own check.
TEST(SessionsE2E, BadInputIsDroppedCountedAndHarmless) {
  const std::string dir = ScratchDir();
  Daemon daemon("e2e-c", {"--log-dir", dir}, dir);
  const json ca = Create(dir, "--scene-file " + PushScene());
  ASSERT_EQ(ca["tools"], json::array({"grasper"}));
  const int64_t a = ca["session"].get<int64_t>();
  const int64_t b = Create(dir, "hanging")["session"].get<int64_t>();
  const std::vector<uint8_t> token = client::FromHex(ca["token"].get<std::string>());
  const std::vector<uint8_t> token_b = client::TokenStore(dir + "/sessions.json").Find(b)->token;

  bus::LcmBus probe(kUrl);
  const std::string pose_a = bus::SessionChannel(bus::kPosePrefix, a);
  int64_t expected_a = 0;
  // sends one bad datagram with `send`, then waits until a's status has counted exactly one
  // more rejection, for the reason `why`
  auto expect_rejected = [&](const std::string& what, const std::function<void()>& send,
                             const std::string& why) {
    SCOPED_TRACE(what);
    send();
    ++expected_a;
    const json s = StatusWhen(
        dir, a, [&](const json& s) { return s["rejected"].get<int64_t>() >= expected_a; });
    EXPECT_EQ(s["rejected"], expected_a) << s.dump();
    EXPECT_NE(s["last_error"].get<std::string>().find(why), std::string::npos) << s["last_error"];
  };
  std::mt19937 rng(1234);
  std::vector<uint8_t> garbage(64);
  for (uint8_t& g : garbage) g = static_cast<uint8_t>(rng());
  expect_rejected(
      "garbage", [&] { probe.PublishRaw(pose_a, garbage.data(), 64); },
      "malformed message on " + pose_a);
  expect_rejected(
      "truncated", [&] { probe.PublishRaw(pose_a, garbage.data(), 3); }, "malformed message");
  expect_rejected(
      "another type",
      [&] {
        viscera_proto::heartbeat_t hb{};
        hb.header = bus::MakeHeader(a, 0);
        probe.Publish(pose_a, hb);
      },
      "malformed message");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  expect_rejected(
      "NaN position", [&] { probe.Publish(pose_a, Pose(a, token, 1, Vec3(nan, 0.0, 0.0))); },
      "pose: position (nan");
  expect_rejected(
      "inf orientation",
      [&] {
        auto p = Pose(a, token, 2, Vec3::Zero());
        p.orientation[2] = inf;
        probe.Publish(pose_a, p);
      },
      "pose: orientation quaternion of norm inf");
  expect_rejected(
      "far position", [&] { probe.Publish(pose_a, Pose(a, token, 3, Vec3(1e9, 0.0, 0.0))); },
      "pose: position (1e+09, 0, 0) m: not finite or beyond");
  expect_rejected(
      "jaw out of range",
      [&] {
        auto p = Pose(a, token, 4, Vec3::Zero());
        p.jaw = 5.0;
        probe.Publish(pose_a, p);
      },
      "pose: jaw 5: must be within [0, 1]");
  expect_rejected(
      "no such tool",
      [&] {
        auto p = Pose(a, token, 5, Vec3::Zero());
        p.tool = 1;
        probe.Publish(pose_a, p);
      },
      "pose: tool 1 does not exist (the scene has 1)");
  expect_rejected(
      "another session's token", [&] { probe.Publish(pose_a, Pose(a, token_b, 6, Vec3::Zero())); },
      "pose with a wrong session token");
  expect_rejected(
      "no token", [&] { probe.Publish(pose_a, Pose(a, {}, 7, Vec3::Zero())); },
      "pose without the session token");
  expect_rejected(
      "another protocol version",
      [&] {
        auto p = Pose(a, token, 8, Vec3::Zero());
        p.header.version = viscera_proto::header_t::kProtocolVersion + 1;
        probe.Publish(pose_a, p);
      },
      "pose: protocol version");
  // a stale pose: after a good one (seq 1000), an older seq sent earlier (a reordered datagram)
  const auto good = Pose(a, token, 1000, Vec3(0.0, 0.0, 0.2));
  probe.Publish(pose_a, good);
  StatusWhen(dir, a, [](const json& s) { return s["poses"].get<int64_t>() == 1; });
  expect_rejected(
      "stale pose",
      [&] {
        auto p = Pose(a, token, 999, Vec3(0.0, 0.0, 0.2));
        p.header.utime = good.header.utime - 1000;
        probe.Publish(pose_a, p);
      },
      "stale pose (seq 999 after a newer one)");
  expect_rejected(
      "a destroy with another session's token",
      [&] {
        std::ofstream(dir + "/token_b") << client::ToHex(token_b);
        EXPECT_EQ(
            Viscera(dir, "destroy " + std::to_string(a) + " --token-file " + dir + "/token_b").rc,
            4);
      },
      "request with a wrong session token");
  // a request of another protocol version is answered, in this version's layout, kBadRequest
  {
    SCOPED_TRACE("request of another version");
    std::vector<viscera_proto::session_reply_t> replies;
    probe.Subscribe<viscera_proto::session_reply_t>(
        bus::kReplyChannel, [&](const viscera_proto::session_reply_t& r, int64_t) {
          if (r.request_id == 4242) replies.push_back(r);
        });
    viscera_proto::session_request_t request{};
    request.header = bus::MakeHeader(a, 1);
    request.header.version = viscera_proto::header_t::kProtocolVersion - 1;
    request.request_id = 4242;
    request.command = viscera_proto::session_request_t::kStatus;
    probe.Publish(bus::kRequestChannel, request);
    ++expected_a;  // charged to the session it names
    ASSERT_TRUE(Eventually([&] { return !replies.empty(); }, 30.0, [&] { probe.Pump(20); }));
    EXPECT_EQ(replies[0].result, viscera_proto::session_reply_t::kBadRequest);
    EXPECT_NE(replies[0].message.find("protocol version"), std::string::npos) << replies[0].message;
    const json s = StatusWhen(
        dir, a, [&](const json& s) { return s["rejected"].get<int64_t>() >= expected_a; });
    EXPECT_EQ(s["rejected"], expected_a);
  }
  // a pose whose header names b, on a's channel: charged to b (the session it claims), not a
  {
    SCOPED_TRACE("session id that does not match its channel");
    probe.Publish(pose_a, Pose(b, token_b, 1, Vec3::Zero()));
    const json sb =
        StatusWhen(dir, b, [](const json& s) { return s["rejected"].get<int64_t>() >= 1; });
    EXPECT_EQ(sb["rejected"], 1);
    EXPECT_EQ(sb["poses"], 0);
    EXPECT_EQ(sb["last_error"], "pose for session " + std::to_string(b) + " on channel " + pose_a);
  }
  // garbage on every other channel of the protocol, and an unknown session's pose: counted by
  // the server, charged to no session; the pose apart, as not ours (another server's, on a
  // shared bus), not as rejected
  const CliResult before = Viscera(dir, "servers --timeout 1.2 --json");
  ASSERT_EQ(before.rc, 0);
  const int64_t server_rejected = before.json()[0]["rejected"].get<int64_t>();
  const int64_t server_not_ours = before.json()[0]["not_ours"].get<int64_t>();
  for (const std::string& channel :
       {std::string(bus::kRequestChannel), std::string(bus::kReplyChannel),
        std::string(bus::kHeartbeatChannel), bus::SessionChannel(bus::kForcePrefix, a),
        bus::SessionChannel(bus::kStatusPrefix, a), bus::SessionChannel(bus::kSkeletonPrefix, a),
        bus::SessionChannel(bus::kFramePrefix, a)}) {
    probe.PublishRaw(channel, garbage.data(), static_cast<int>(garbage.size()));
  }
  probe.Publish(bus::SessionChannel(bus::kPosePrefix, 999), Pose(999, token, 0, Vec3::Zero()));
  // the server subscribes to requests, heartbeats (other servers, for placement) and poses only:
  // the request and heartbeat garbage rejected, the unknown pose not ours
  int64_t now_rejected = 0, now_not_ours = 0;
  EXPECT_TRUE(Eventually(
      [&] {
        const CliResult r = Viscera(dir, "servers --timeout 1.2 --json");
        if (r.rc == 0) {
          now_rejected = r.json()[0]["rejected"].get<int64_t>();
          now_not_ours = r.json()[0]["not_ours"].get<int64_t>();
        }
        return now_rejected >= server_rejected + 2 && now_not_ours >= server_not_ours + 1;
      },
      30.0))
      << "the server did not count the garbage request and heartbeat and the unknown session's "
         "pose";
  EXPECT_EQ(now_rejected, server_rejected + 2);
  EXPECT_EQ(now_not_ours, server_not_ours + 1);
  json sa = Status(dir, a);
  EXPECT_EQ(sa["rejected"], expected_a);
  EXPECT_EQ(sa["poses"], 1);

  // a flood: 20000 good poses as fast as the bus takes them. UDP on loopback may lose some;
  // none is rejected, none reaches b, and both sessions keep running.
  for (int64_t k = 0; k < 20000; ++k)
    probe.Publish(pose_a, Pose(a, token, 2000 + k, Vec3(0.0, 0.0, 0.3)));
  probe.Publish(pose_a, Pose(a, token, 30000, Vec3(0.0, 0.0, 0.3)));  // a last one, paced
  sa = StatusWhen(dir, a, [](const json& s) { return s["poses"].get<int64_t>() > 200; });
  ASSERT_TRUE(daemon.Alive());
  EXPECT_EQ(sa["state"], "running");
  EXPECT_EQ(sa["rejected"], expected_a) << sa.dump();
  EXPECT_LE(sa["poses"].get<int64_t>(), 1 + 20000 + 1);
  const json sb = Status(dir, b);
  EXPECT_EQ(sb["state"], "running");
  EXPECT_EQ(sb["rejected"], 1);  // the mismatched pose above, nothing of the flood
  EXPECT_EQ(sb["poses"], 0);

  // nothing recorded was lost: a's record, poses and forces, replays exactly
  EXPECT_EQ(Viscera(dir, "destroy " + std::to_string(a)).rc, 0);
  const session::ReplayResult r =
      session::ReplayRecord(dir + "/session-" + std::to_string(a) + ".lcmlog");
  EXPECT_GT(r.steps, 50);
  EXPECT_GT(r.skeletons_compared, 10);
  EXPECT_EQ(r.max_deviation, 0.0);
  EXPECT_EQ(r.forces_compared, r.steps);
  EXPECT_EQ(r.force_mismatches, 0) << r.first_force_mismatch;
  EXPECT_EQ(daemon.Stop(), 0);
}

}  // namespace
}  // namespace viscera::e2e
