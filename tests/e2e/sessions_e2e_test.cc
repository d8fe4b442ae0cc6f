// End to end: the real viscerad and the real viscera over real UDP multicast, inside a
// private loopback-only network namespace (tests/e2e/in_netns.sh runs every test).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <viscera_proto/force_feedback_t.hpp>
#include <viscera_proto/heartbeat_t.hpp>
#include <viscera_proto/session_status_t.hpp>
#include <viscera_proto/tool_pose_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/lcm_bus.h"
#include "client/token_store.h"
#include "common/clock.h"
#include "session/replay.h"
#include "tests/e2e/e2e_harness.h"

namespace viscera::e2e {
namespace {

using nlohmann::json;


std::string PushScene() { return std::string(VISCERA_SOURCE_DIR) + "/tests/e2e/scenes/push.toml"; }

viscera_proto::tool_pose_t Pose(int64_t id, const std::vector<uint8_t>& token, int64_t seq,
                                const Vec3& p) {
  viscera_proto::tool_pose_t pose{};
  pose.header = bus::MakeHeader(id, seq);
  pose.header.token = token;
  pose.header.token_len = static_cast<int32_t>(token.size());
  pose.tool = 0;
  for (int a = 0; a < 3; ++a) pose.position[a] = p(a);
  pose.orientation[0] = 1.0;
  pose.jaw = 1.0;
  return pose;
}

TEST(SessionsE2E, CreateStatusListDestroy) {
  const std::string dir = ScratchDir();
  // no server yet: a clear error and exit status 2, within the timeout
  const CliResult none = Viscera(dir, "status 1 --timeout 0.5 --json");
  EXPECT_EQ(none.rc, 2);
  EXPECT_EQ(Viscera(dir, "create fall --timeout 0.5").rc, 2);

  Daemon daemon("e2e-a", {}, dir);
  const json created = Create(dir, "fall");
  const int64_t id = created["session"].get<int64_t>();
  EXPECT_GT(id, 0);
  EXPECT_EQ(created["server_id"], "e2e-a");
  EXPECT_EQ(created["token"].get<std::string>().size(), 32u);  // 16 random bytes
  Sleep(1.5);
  const json s = Status(dir, id);
  EXPECT_EQ(s["session"], id);
  EXPECT_EQ(s["state"], "running");
  EXPECT_GT(s["sim_time"].get<double>(), 1.0);
  // the rate achieved, and deadlines kept; the bounds leave room for this shared 2-core
  // machine, where ctest runs other tests (and other people build) at the same time
  EXPECT_NEAR(s["rate_hz"].get<double>(), 100.0, 15.0) << s.dump();
  EXPECT_LE(s["deadline_misses"].get<int64_t>(), s["steps"].get<int64_t>() / 50) << s.dump();
  EXPECT_EQ(s["rejected"], 0);

  const CliResult list = Viscera(dir, "list --json");
  ASSERT_EQ(list.rc, 0);
  ASSERT_EQ(list.json().size(), 1u);
  EXPECT_EQ(list.json()[0]["session"], id);
  EXPECT_EQ(list.json()[0]["state"], "running");

  EXPECT_EQ(Viscera(dir, "pause " + std::to_string(id)).rc, 0);
  Sleep(0.6);
  EXPECT_EQ(Status(dir, id)["state"], "paused");
  EXPECT_EQ(Viscera(dir, "resume " + std::to_string(id)).rc, 0);
  EXPECT_EQ(Viscera(dir, "reset " + std::to_string(id)).rc, 0);
  EXPECT_EQ(Viscera(dir, "camera " + std::to_string(id) + " --eye 0 -0.3 0.3 --target 0 0 0").rc, 0);

  const CliResult destroyed = Viscera(dir, "destroy " + std::to_string(id) + " --json");
  ASSERT_EQ(destroyed.rc, 0);
  EXPECT_EQ(destroyed.json()["status"]["state"], "stopped");
  EXPECT_EQ(Viscera(dir, "status " + std::to_string(id)).rc, 3);  // unknown session
  EXPECT_EQ(Viscera(dir, "destroy " + std::to_string(id)).rc, 3);
  EXPECT_EQ(Viscera(dir, "create no-such-scene").rc, 4);           // refused, with a reason
  EXPECT_EQ(daemon.Stop(), 0);
  EXPECT_NE(daemon.Stderr().find("stopped cleanly"), std::string::npos);
}

TEST(SessionsE2E, TwoSessionsStayIsolated) {
  const std::string dir = ScratchDir();
  Daemon daemon("e2e-b", {}, dir);
  const int64_t a = Create(dir, "fall")["session"].get<int64_t>();
  const int64_t b = Create(dir, "hanging --rate 200")["session"].get<int64_t>();
  ASSERT_NE(a, b);
  bus::LcmBus probe(kUrl);
  int statuses_of_b_on_a = 0;
  probe.Subscribe<viscera_proto::session_status_t>(
      bus::SessionChannel(bus::kStatusPrefix, a), [&](const viscera_proto::session_status_t& s, int64_t) {
        if (s.header.session_id != a) ++statuses_of_b_on_a;
      });
  // a's token does not drive b
  client::TokenStore store(dir + "/sessions.json");
  const std::string token_a = client::ToHex(store.Find(a)->token);
  EXPECT_EQ(Viscera(dir, "pause " + std::to_string(b) + " --token " + token_a).rc, 4);
  EXPECT_EQ(Viscera(dir, "pause " + std::to_string(a)).rc, 0);
  const int64_t deadline = MonotonicNanos() + 1'500'000'000;
  while (MonotonicNanos() < deadline) probe.Pump(50);
  const json sa = Status(dir, a), sb = Status(dir, b);
  EXPECT_EQ(sa["state"], "paused");
  EXPECT_EQ(sb["state"], "running");
  EXPECT_NEAR(sb["rate_hz"].get<double>(), 200.0, 20.0);
  EXPECT_EQ(sb["configured_rate_hz"], 200.0);
  EXPECT_EQ(sa["rejected"], 0);
  EXPECT_EQ(sb["rejected"], 1);  // the pause with a's token
  EXPECT_EQ(statuses_of_b_on_a, 0);
  EXPECT_EQ(Viscera(dir, "destroy " + std::to_string(a)).rc, 0);
  Sleep(0.3);
  EXPECT_EQ(Status(dir, b)["state"], "running");
  EXPECT_EQ(Viscera(dir, "list --json").json().size(), 1u);
}

TEST(SessionsE2E, BadInputIsDroppedCountedAndHarmless) {
  const std::string dir = ScratchDir();
  Daemon daemon("e2e-c", {"--log-dir", dir}, dir);
  const json ca = Create(dir, "fall");
  const int64_t a = ca["session"].get<int64_t>();
  const int64_t b = Create(dir, "hanging")["session"].get<int64_t>();
  const std::vector<uint8_t> token = client::FromHex(ca["token"].get<std::string>());
  const std::vector<uint8_t> token_b =
      client::TokenStore(dir + "/sessions.json").Find(b)->token;

  bus::LcmBus probe(kUrl);
  const std::string pose_a = bus::SessionChannel(bus::kPosePrefix, a);
  std::mt19937 rng(1234);
  std::vector<uint8_t> garbage(64);
  for (uint8_t& g : garbage) g = static_cast<uint8_t>(rng());
  // garbage on every channel of the protocol
  for (const std::string& channel :
       {std::string(bus::kRequestChannel), std::string(bus::kReplyChannel),
        std::string(bus::kHeartbeatChannel), pose_a, bus::SessionChannel(bus::kForcePrefix, a),
        bus::SessionChannel(bus::kStatusPrefix, a), bus::SessionChannel(bus::kSkeletonPrefix, a),
        bus::SessionChannel(bus::kFramePrefix, a)}) {
    probe.PublishRaw(channel, garbage.data(), static_cast<int>(garbage.size()));
  }
  probe.PublishRaw(pose_a, garbage.data(), 3);  // truncated
  // a message of the wrong type on the pose channel
  viscera_proto::heartbeat_t hb{};
  hb.header = bus::MakeHeader(a, 0);
  probe.Publish(pose_a, hb);
  // NaN, inf, huge values
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  probe.Publish(pose_a, Pose(a, token, 1, Vec3(nan, 0.0, 0.0)));
  auto bad_orientation = Pose(a, token, 2, Vec3::Zero());
  bad_orientation.orientation[2] = inf;
  probe.Publish(pose_a, bad_orientation);
  probe.Publish(pose_a, Pose(a, token, 3, Vec3(1e9, 0.0, 0.0)));
  auto bad_jaw = Pose(a, token, 4, Vec3::Zero());
  bad_jaw.jaw = 5.0;
  probe.Publish(pose_a, bad_jaw);
  // wrong and missing token, another protocol version
  probe.Publish(pose_a, Pose(a, token_b, 5, Vec3::Zero()));
  probe.Publish(pose_a, Pose(a, {}, 6, Vec3::Zero()));
  auto old = Pose(a, token, 7, Vec3::Zero());
  old.header.version = 1;
  probe.Publish(pose_a, old);
  const int kBadForA = 10;  // 2 garbage + 1 wrong type + 4 bad values + 2 tokens + 1 version
  // an unknown session, and a destroy with a wrong token
  probe.Publish(bus::SessionChannel(bus::kPosePrefix, 999), Pose(999, token, 0, Vec3::Zero()));
  EXPECT_EQ(Viscera(dir, "destroy " + std::to_string(a) + " --token " + client::ToHex(token_b)).rc, 4);
  // a flood: 20000 poses as fast as the bus takes them
  for (int64_t k = 0; k < 20000; ++k) probe.Publish(pose_a, Pose(a, token, 100 + k, Vec3(0.0, 0.0, 0.3)));
  Sleep(1.5);

  ASSERT_TRUE(daemon.Alive());
  const json sa = Status(dir, a), sb = Status(dir, b);
  EXPECT_EQ(sa["state"], "running");
  EXPECT_EQ(sb["state"], "running");
  // the flood's poses are accepted (a scene with tools) or rejected as tool-less; the others
  // are counted exactly (UDP on loopback may lose some of the flood, not the first ones)
  const int64_t flood_counted = sa["poses"].get<int64_t>() + sa["rejected"].get<int64_t>() - kBadForA - 1;
  EXPECT_GE(sa["rejected"].get<int64_t>(), kBadForA + 1) << sa.dump();
  EXPECT_LE(flood_counted, 20000);
  EXPECT_GT(flood_counted, 200) << "the server heard almost none of the flood";
  EXPECT_NE(sa["last_error"].get<std::string>(), "");
  EXPECT_EQ(sb["rejected"], 0);  // the other session saw none of it
  EXPECT_NEAR(sb["rate_hz"].get<double>(), 100.0, 10.0);
  EXPECT_NEAR(sa["rate_hz"].get<double>(), 100.0, 10.0);

  // the server counts everything it dropped, the unknown session's pose and garbage requests too
  const CliResult servers = Viscera(dir, "servers --timeout 1.2 --json");
  ASSERT_EQ(servers.rc, 0);
  EXPECT_GE(servers.json()[0]["rejected"].get<int64_t>(), kBadForA + 3);

  // nothing recorded was lost: a's record replays exactly
  EXPECT_EQ(Viscera(dir, "destroy " + std::to_string(a)).rc, 0);
  const session::ReplayResult r = session::ReplayRecord(dir + "/session-" + std::to_string(a) + ".lcmlog");
  EXPECT_GT(r.steps, 150);
  EXPECT_GT(r.skeletons_compared, 30);
  EXPECT_EQ(r.max_deviation, 0.0);
  EXPECT_EQ(daemon.Stop(), 0);
}

TEST(SessionsE2E, AMechanicalBlowUpIsRecoveredAndReported) {
  const std::string dir = ScratchDir();
  const std::string unstable = dir + "/unstable.toml";
  std::ofstream(unstable) << "[simulation]\nrate_hz = 100\nsubsteps = 1\nintegrator = \"rk4\"\n"
                             "[intestine]\nlength = 0.5\nradius = 0.0125\nmass = 0.12\n"
                             "control_points = 41\nstretch_stiffness = 1.0e4\nbend_stiffness = 1.0e-4\n"
                             "[intestine.shape]\nkind = \"serpentine\"\nstart = [0.0, 0.0, 0.1]\n"
                             "amplitude = 0.05\nwavelength = 0.2\n";
  Daemon daemon("e2e-d", {}, dir);
  const int64_t good = Create(dir, "fall")["session"].get<int64_t>();
  const int64_t bad = Create(dir, "--scene-file " + unstable)["session"].get<int64_t>();
  Sleep(1.5);
  const json sb = Status(dir, bad), sg = Status(dir, good);
  EXPECT_EQ(sb["state"], "running");
  EXPECT_GT(sb["recoveries"].get<int64_t>(), 0);
  EXPECT_NE(sb["last_error"].get<std::string>().find("blew up"), std::string::npos);
  EXPECT_TRUE(std::isfinite(sb["energy"].get<double>()));
  EXPECT_EQ(sg["recoveries"], 0);
  EXPECT_NEAR(sg["rate_hz"].get<double>(), 100.0, 10.0);
}

TEST(SessionsE2E, WithAPreSharedKeyOnlyKeyHoldersCreateOrDrive) {
  const std::string dir = ScratchDir();
  ASSERT_EQ(Viscera(dir, "keygen " + dir + "/psk").rc, 0);
  Daemon daemon("e2e-e", {"--key-file", dir + "/psk"}, dir);
  // without the key: the server drops the request unanswered
  EXPECT_EQ(Viscera(dir, "create fall --timeout 1.5").rc, 2);
  const json created = Create(dir, "fall --key-file " + dir + "/psk");
  const int64_t id = created["session"].get<int64_t>();
  const std::vector<uint8_t> token = client::FromHex(created["token"].get<std::string>());
  // a datagram with the right token but no MAC (what a LAN host could send): dropped
  bus::LcmBus unsigned_probe(kUrl);
  unsigned_probe.Publish(bus::SessionChannel(bus::kPosePrefix, id), Pose(id, token, 0, Vec3::Zero()));
  EXPECT_EQ(Viscera(dir, "destroy " + std::to_string(id) + " --timeout 1").rc, 2);
  Sleep(0.3);
  const CliResult s = Viscera(dir, "status " + std::to_string(id) + " --json --key-file " + dir + "/psk");
  ASSERT_EQ(s.rc, 0);
  EXPECT_EQ(s.json()["state"], "running");
  EXPECT_EQ(s.json()["rejected"], 1);  // the unsigned pose, charged to its session
  EXPECT_EQ(s.json()["poses"], 0);
  EXPECT_EQ(Viscera(dir, "destroy " + std::to_string(id) + " --key-file " + dir + "/psk").rc, 0);
}

TEST(SessionsE2E, ARecordSurvivesAKilledServerAndReplays) {
  const std::string dir = ScratchDir();
  Daemon daemon("e2e-f", {"--log-dir", dir}, dir);
  const int64_t id = Create(dir, "fall")["session"].get<int64_t>();
  EXPECT_EQ(Viscera(dir, "reset " + std::to_string(id)).rc, 0);
  Sleep(1.0);
  EXPECT_EQ(daemon.Stop(SIGKILL), 128 + SIGKILL);  // no chance to flush
  const session::ReplayResult r = session::ReplayRecord(dir + "/session-" + std::to_string(id) + ".lcmlog");
  EXPECT_EQ(r.session_id, id);
  EXPECT_EQ(r.resets, 1);
  EXPECT_GT(r.steps, 80);  // at most a fraction of a second lost
  EXPECT_GT(r.skeletons_compared, 20);
  EXPECT_EQ(r.max_deviation, 0.0);
  // The offline runner replays the same record to the same trajectory.
  const std::string trace = dir + "/replay.jsonl";
  FILE* pipe = popen((std::string(VISCERA_SIM) + " --replay " + dir + "/session-" + std::to_string(id) +
                      ".lcmlog --json --trace " + trace + " 2>&1").c_str(), "r");
  std::string out;
  char buf[4096];
  for (size_t n; (n = fread(buf, 1, sizeof buf, pipe)) > 0;) out.append(buf, n);
  ASSERT_EQ(pclose(pipe), 0) << out;
  const json replayed = json::parse(out);
  EXPECT_EQ(replayed["steps"], r.steps);
  EXPECT_EQ(replayed["skeletons_compared"], r.skeletons_compared);
  EXPECT_EQ(replayed["max_deviation"], 0.0);
  EXPECT_EQ(replayed["frames"], r.steps + r.resets);  // a frame per replayed step and reset
}

TEST(SessionsE2E, ToolPushGivesAnOpposingForce) {
  const std::string dir = ScratchDir();
  Daemon daemon("e2e-g", {}, dir);
  const json created = Create(dir, "--scene-file " + PushScene());
  ASSERT_FALSE(created["tools"].empty()) << created.dump();
  const int64_t id = created["session"].get<int64_t>();
  EXPECT_EQ(created["tools"], json::array({"grasper"}));
  // press the tip 1 cm into the tube lying on the floor (its top is at z = 0.025 m)
  const std::string script = dir + "/push.csv";
  std::ofstream(script) << "t,tool,x,y,z,qw,qx,qy,qz,jaw\n0,grasper,0,0,0.1,1,0,0,0,1\n"
                           "1,grasper,0,0,0.03,1,0,0,0,1\n2,grasper,0,0,0.015,1,0,0,0,1\n"
                           "3,grasper,0,0,0.015,1,0,0,0,1\n";
  const CliResult r = Viscera(dir, "drive " + std::to_string(id) + " --script " + script + " --json");
  ASSERT_EQ(r.rc, 0) << r.out;
  const json d = r.json()["drive"];
  EXPECT_GT(d["max_force_n"].get<double>(), 0.05) << d.dump();
  EXPECT_GT(d["force_at_max"][2].get<double>(), 0.0) << "pushing down must push the hand up";
}

TEST(SessionsE2E, AClientThatStopsSendingLetsTheToolGoIdleAndTheForceFade) {
  const std::string dir = ScratchDir();
  Daemon daemon("e2e-h", {}, dir);
  const int64_t other = Create(dir, "fall")["session"].get<int64_t>();
  const json created = Create(dir, "--scene-file " + PushScene());
  ASSERT_EQ(created["tools"], json::array({"grasper"}));
  const int64_t id = created["session"].get<int64_t>();
  const std::vector<uint8_t> token = client::FromHex(created["token"].get<std::string>());
  bus::LcmBus probe(kUrl);
  std::vector<viscera_proto::force_feedback_t> forces;
  probe.Subscribe<viscera_proto::force_feedback_t>(
      bus::SessionChannel(bus::kForcePrefix, id),
      [&](const viscera_proto::force_feedback_t& f, int64_t) { forces.push_back(f); });
  const std::string channel = bus::SessionChannel(bus::kPosePrefix, id);
  // press into the tube for 1.5 s at 200 Hz, plus a flood of 5000 identical poses at once
  int64_t seq = 0;
  for (int k = 0; k < 300; ++k) {
    const double z = std::max(0.015, 0.1 - 0.0015 * k);
    probe.Publish(channel, Pose(id, token, seq++, Vec3(0.0, 0.0, z)));
    if (k == 200) {
      for (int j = 0; j < 5000; ++j) probe.Publish(channel, Pose(id, token, seq++, Vec3(0.0, 0.0, z)));
    }
    probe.Pump(5);
  }
  const size_t pressing = forces.size();
  // then silence
  const int64_t end = MonotonicNanos() + 1'500'000'000;
  while (MonotonicNanos() < end) probe.Pump(20);
  ASSERT_GT(pressing, 100u);
  double max_pressing = 0.0;
  for (size_t i = 0; i < pressing; ++i) {
    if (forces[i].active) max_pressing = std::max(max_pressing, std::abs(forces[i].force[2]));
  }
  EXPECT_GT(max_pressing, 0.05);
  ASSERT_FALSE(forces.empty());
  const auto& last = forces.back();
  EXPECT_FALSE(last.active);
  EXPECT_LT(std::hypot(last.force[0], last.force[1], last.force[2]), 1e-3) << "the force must fade to zero";
  // no jump: the force fades over steps instead of dropping at once
  const json s = Status(dir, id);
  EXPECT_EQ(s["idle_events"], 1);
  // the 300 paced poses arrive; of the burst, UDP keeps what the receive buffer holds
  EXPECT_GT(s["poses"].get<int64_t>(), 250) << s.dump();
  const json so = Status(dir, other);
  EXPECT_NEAR(so["rate_hz"].get<double>(), 100.0, 15.0) << so.dump();  // unaffected
  EXPECT_NEAR(s["rate_hz"].get<double>(), 100.0, 15.0) << s.dump();
}

}  // namespace
}  // namespace viscera::e2e
