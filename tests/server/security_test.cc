// Replay protection, leases, limits and hostile scenes at the SessionManager (docs/security.md).
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <viscera_proto/session_status_t.hpp>

#include "bus/message_auth.h"
#include "server/scene_budget.h"
#include "tests/common/eventually.h"
#include "tests/server/manager_fixture.h"

namespace viscera::server {
namespace {

using R = viscera_proto::session_reply_t;
using Q = viscera_proto::session_request_t;

std::string SceneText(const std::string& name) {
  std::ifstream in(std::string(VISCERA_SOURCE_DIR) + "/scenes/" + name);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A small valid scene with one mesh obstacle naming `file` (the tube starts clear of it).
std::string SceneWithMesh(const std::string& file) {
  return "[intestine]\nlength = 0.4\nradius = 0.0125\nmass = 0.1\ncontrol_points = 21\n"
         "[intestine.shape]\nkind = \"straight\"\nstart = [0.0, 0.0, 0.3]\n"
         "[[obstacle]]\nkind = \"mesh\"\nfile = \"" +
         file + "\"\nscale = 0.05\n";
}

std::string TempDir(const std::string& name) {
  const std::string dir =
      ::testing::TempDir() + "/viscera_security_" + name + "_" + std::to_string(getpid());
  std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "'").c_str());
  return dir;
}

class SecurityTest : public SessionManagerTest {
 protected:
  Q WithToken(Q r, const R& created) {
    r.header.token = created.header.token;
    r.header.token_len = static_cast<int32_t>(created.header.token.size());
    return r;
  }
  R CreateHanging() {
    Q create = Request(Q::kCreate);
    create.scene_name = "hanging";
    create.frame_rate_hz = -1.0;
    return Ask(create);
  }
  viscera_proto::session_status_t StatusOf(int64_t id) {
    const R r = Ask(Request(Q::kStatus, id));
    EXPECT_EQ(r.num_sessions, 1);
    return r.num_sessions == 1 ? r.sessions[0] : viscera_proto::session_status_t{};
  }
  R RefusedCreate(const std::string& toml, const std::string& fragment) {
    Q create = Request(Q::kCreate);
    create.scene_toml = toml;
    create.frame_rate_hz = -1.0;
    const R reply = Ask(create);
    EXPECT_EQ(reply.result, R::kRefused) << fragment;
    EXPECT_NE(reply.message.find(fragment), std::string::npos) << reply.message;
    EXPECT_EQ(manager_->num_sessions(), 0);
    return reply;
  }
};

TEST_F(SecurityTest, AReplayedCommandIsRefusedCountedAndChangesNothing) {
  const R created = CreateHanging();
  ASSERT_EQ(created.result, R::kOk) << created.message;
  const int64_t id = created.header.session_id;
  const Q pause = Stamp(WithToken(Request(Q::kPause, id), created));
  ASSERT_EQ(Deliver(pause).result, R::kOk);
  ASSERT_EQ(Ask(WithToken(Request(Q::kResume, id), created)).result, R::kOk);
  const R replayed = Deliver(pause);  // the captured pause, sent again as it was
  EXPECT_EQ(replayed.result, R::kReplayed);
  EXPECT_NE(replayed.message.find("replayed"), std::string::npos) << replayed.message;
  const auto status = StatusOf(id);
  EXPECT_EQ(status.replayed, 1);
  EXPECT_GE(status.rejected, 1);
  // the resume stands: the loop applies commands between steps, so wait for it to step on
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  int64_t steps = StatusOf(id).steps;
  while (StatusOf(id).steps <= steps + 1 && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(StatusOf(id).state, viscera_proto::session_status_t::kRunning);
  EXPECT_GT(StatusOf(id).steps, steps);
  EXPECT_EQ(manager_->replayed(), 1);
}

TEST_F(SecurityTest, StaleAndFutureCommandsAndCreatesAreRefused) {
  const R created = CreateHanging();
  ASSERT_EQ(created.result, R::kOk) << created.message;
  const int64_t id = created.header.session_id;
  const int64_t skew = static_cast<int64_t>(config_.max_clock_skew_s * 1e6);
  for (const int64_t offset : {-2 * skew, 2 * skew}) {
    Q pause = Stamp(WithToken(Request(Q::kPause, id), created));
    pause.header.utime += offset;
    const R reply = Deliver(pause);
    EXPECT_EQ(reply.result, R::kReplayed);
    EXPECT_NE(reply.message.find("stale"), std::string::npos) << reply.message;
  }
  Q create = Request(Q::kCreate);
  create.scene_name = "hanging";
  create = Stamp(create);
  create.header.utime -= 2 * skew;
  EXPECT_EQ(Deliver(create).result, R::kReplayed);
  EXPECT_EQ(StatusOf(id).replayed, 2);
  EXPECT_EQ(StatusOf(id).state, viscera_proto::session_status_t::kRunning);
  EXPECT_EQ(manager_->replayed(), 3);
}

TEST_F(SecurityTest, ASessionWithoutClientTrafficEndsAfterItsLeaseWithItsRecordComplete) {
  ServerConfig config = config_;
  config.session_lease_s = 0.6;
  config.max_sessions = 2;
  config.log_dir = TempDir("lease");
  Restart(config);
  // Both creates at once: built one after the other, the first session would hear nothing
  // while the second builds, which takes longer than the lease on a busy machine.
  Q create = Request(Q::kCreate);
  create.scene_name = "hanging";
  create.frame_rate_hz = -1.0;
  const Q create_idle = Stamp(create);
  const Q create_kept = Stamp(create);
  const std::string channel = bus::kRequestChannel;
  const bus::MessageInfo info{&channel, 0, 0};
  manager_->OnRequest(create_idle, info);
  manager_->OnRequest(create_kept, info);
  const auto reply_to = [&](const Q& q) {
    for (const R& r : replies_) {
      if (r.request_id == q.request_id) return r;
    }
    return R{};
  };
  // the kept one is kept alive from its creation on, while the other may still build
  auto next_keep_alive = std::chrono::steady_clock::now();
  const auto keep_alive = [&] {
    const R kept = reply_to(create_kept);
    if (kept.result != R::kOk || std::chrono::steady_clock::now() < next_keep_alive) return;
    manager_->OnRequest(Stamp(WithToken(Request(Q::kKeepAlive, kept.header.session_id), kept)),
                        info);
    next_keep_alive = std::chrono::steady_clock::now() + std::chrono::milliseconds(100);
  };
  ASSERT_TRUE(viscera::testing::Eventually([&] { return !manager_->creating(); }, 60.0,
                                           [&] {
                                             std::this_thread::sleep_for(
                                                 std::chrono::milliseconds(5));
                                             manager_->Poll();
                                             bus_.Drain();
                                             keep_alive();
                                           }));
  bus_.Drain();
  const R idle = reply_to(create_idle);
  const R kept = reply_to(create_kept);
  ASSERT_EQ(idle.result, R::kOk) << idle.message;
  ASSERT_EQ(kept.result, R::kOk) << kept.message;
  // the lease, as the create's reply reports it (a status asked later races the lease)
  ASSERT_EQ(idle.num_sessions, 1);
  EXPECT_LE(idle.sessions[0].lease_left_s, 0.6);
  EXPECT_DOUBLE_EQ(idle.sessions[0].lease_s, 0.6);
  // keep-alives keep one alive; the other hears nothing and ends
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (manager_->num_sessions() == 2 && std::chrono::steady_clock::now() < give_up) {
    ASSERT_EQ(Ask(WithToken(Request(Q::kKeepAlive, kept.header.session_id), kept)).result, R::kOk);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    manager_->Poll();
  }
  EXPECT_EQ(manager_->num_sessions(), 1);
  EXPECT_EQ(manager_->expired(), 1);
  EXPECT_EQ(Ask(Request(Q::kStatus, idle.header.session_id)).result, R::kUnknownSession);
  EXPECT_EQ(StatusOf(kept.header.session_id).state, viscera_proto::session_status_t::kRunning);

  // the record ends with the final status, which says why
  lcm::LogFile log(
      config.log_dir + "/session-" + std::to_string(idle.header.session_id) + ".lcmlog", "r");
  ASSERT_TRUE(log.good());
  viscera_proto::session_status_t last{};
  int statuses = 0;
  const std::string status_channel =
      bus::SessionChannel(bus::kStatusPrefix, idle.header.session_id);
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    if (e->channel != status_channel) continue;
    ASSERT_EQ(last.decode(e->data, 0, e->datalen), e->datalen);
    ++statuses;
  }
  EXPECT_GT(statuses, 0);
  EXPECT_EQ(last.state, viscera_proto::session_status_t::kStopped);
  EXPECT_NE(last.last_error.find("lease expired"), std::string::npos) << last.last_error;
}

TEST_F(SecurityTest, RecordsHoldNoTokens) {
  ServerConfig config = config_;
  config.log_dir = TempDir("tokens");
  Restart(config);
  const R created = CreateHanging();
  ASSERT_EQ(created.result, R::kOk) << created.message;
  const int64_t id = created.header.session_id;
  ASSERT_EQ(Ask(WithToken(Request(Q::kPause, id), created)).result, R::kOk);
  ASSERT_EQ(Ask(WithToken(Request(Q::kResume, id), created)).result, R::kOk);
  manager_->StopAll();
  std::ifstream in(config.log_dir + "/session-" + std::to_string(id) + ".lcmlog", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 1000u);
  const std::string token(created.header.token.begin(), created.header.token.end());
  EXPECT_EQ(bytes.find(token), std::string::npos) << "the session token is in its record";
}

TEST_F(SecurityTest, EachLimitRefusesACreateWithTheReason) {
  const ServerConfig base = config_;
  const auto with = [&](auto change) {
    ServerConfig config = base;
    change(&config);
    Restart(config);
  };
  const std::string cavity = SceneText("cavity.toml");
  with([](ServerConfig* c) { c->max_control_points = 100; });
  RefusedCreate(cavity, "intestine.control_points = 190: above this server's limit of 100");
  with([](ServerConfig* c) { c->max_obstacles = 2; });
  RefusedCreate(cavity, "[[obstacle]] count = 4: above this server's limit of 2");
  with([](ServerConfig* c) { c->max_mesh_resolution = 20; });
  RefusedCreate(cavity, "resolution = 40: above this server's limit of 20");
  with([](ServerConfig* c) { c->max_mesh_bytes = 1000; });
  RefusedCreate(cavity, "bytes: above this server's limit of 1000");
  with([](ServerConfig* c) { c->max_settle_s = 1.0; });
  RefusedCreate(cavity, "simulation.settle = 9: above this server's limit of 1");
  with([](ServerConfig* c) { c->max_substeps = 1; });
  RefusedCreate(cavity, "simulation.substeps = 2: above this server's limit of 1");
  with([](ServerConfig* c) { c->max_session_load = 1e-6; });
  RefusedCreate(SceneText("hanging.toml"), "estimated mechanics load");

  // frame bandwidth: 640 x 480 at 25 Hz is 7.7 Mpixel/s
  with([](ServerConfig* c) { c->max_frame_mpix_per_s = 5.0; });
  Q create = Request(Q::kCreate);
  create.scene_name = "hanging";
  R reply = Ask(create);
  EXPECT_EQ(reply.result, R::kRefused);
  EXPECT_NE(reply.message.find("frame bandwidth"), std::string::npos) << reply.message;
  create.frame_width = 320;
  create.frame_height = 240;
  create.frame_rate_hz = 10.0;  // 0.8 Mpixel/s fits
  reply = Ask(create);
  EXPECT_EQ(reply.result, R::kOk) << reply.message;

  // creates per minute per sender
  with([](ServerConfig* c) {
    c->max_creates_per_minute = 2;
    c->max_sessions = 4;
  });
  EXPECT_EQ(CreateHanging().result, R::kOk);
  EXPECT_EQ(CreateHanging().result, R::kOk);
  reply = CreateHanging();
  EXPECT_EQ(reply.result, R::kRefused);
  EXPECT_NE(reply.message.find("too many creates"), std::string::npos) << reply.message;
  EXPECT_EQ(manager_->num_sessions(), 2);
}

TEST_F(SecurityTest, AnOversizeRequestIsAnsweredWithTheLimit) {
  Q create = Request(Q::kCreate);
  create.scene_toml = std::string(5000, '#');
  create.request_id = 77;
  std::vector<uint8_t> bytes(static_cast<size_t>(create.getEncodedSize()));
  ASSERT_EQ(create.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  manager_->OnDrop(bus::kRequestChannel, bus::DropReason::kOversize, bytes.data(),
                   static_cast<int>(bytes.size()));
  bus_.Drain();
  ASSERT_FALSE(replies_.empty());
  EXPECT_EQ(replies_.back().request_id, 77);
  EXPECT_EQ(replies_.back().result, R::kRefused);
  EXPECT_NE(replies_.back().message.find("--max-message-size"), std::string::npos)
      << replies_.back().message;
  // truncated bytes: nothing to answer, nothing thrown
  const size_t before = replies_.size();
  manager_->OnDrop(bus::kRequestChannel, bus::DropReason::kOversize, bytes.data(), 40);
  bus_.Drain();
  EXPECT_EQ(replies_.size(), before);
}

TEST_F(SecurityTest, InlineScenesNameNoFileOutsideTheSceneDirectory) {
  RefusedCreate(SceneWithMesh("/dev/zero"), "absolute paths are refused");
  RefusedCreate(SceneWithMesh("/etc/passwd"), "absolute paths are refused");
  RefusedCreate(SceneWithMesh("../CMakeLists.txt"), "\"..\" is refused");
  RefusedCreate(SceneWithMesh("sub/../../x.obj"), "\"..\" is refused");
  RefusedCreate(SceneWithMesh("missing.obj"), "no such file");
  // the scene directory's own files are fine
  Q create = Request(Q::kCreate);
  create.scene_toml = SceneWithMesh("liver.obj");
  create.frame_rate_hz = -1.0;
  const R ok = Ask(create);
  EXPECT_EQ(ok.result, R::kOk) << ok.message;
}

TEST(ResolveSceneFile, RefusesLinksOutDevicesFifosAndLargeFiles) {
  const std::string dir = TempDir("files");
  ASSERT_EQ(symlink("/dev/zero", (dir + "/zero.obj").c_str()), 0);
  ASSERT_EQ(symlink("/etc/passwd", (dir + "/passwd.obj").c_str()), 0);
  ASSERT_EQ(mkfifo((dir + "/fifo.obj").c_str(), 0600), 0);
  ASSERT_EQ(mkdir((dir + "/dir.obj").c_str(), 0700), 0);
  std::ofstream(dir + "/big.obj") << std::string(2000, 'v');
  std::ofstream(dir + "/ok.obj") << "v 0 0 0\n";
  const auto refused = [&](const std::string& file, const std::string& why) {
    try {
      ResolveSceneFile(dir, file, 1000);
      ADD_FAILURE() << file << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  refused("zero.obj", "outside the server's scene directory");
  refused("passwd.obj", "outside the server's scene directory");
  refused("fifo.obj", "not a regular file");  // and nothing blocked on opening it
  refused("dir.obj", "not a regular file");
  refused("big.obj", "2000 bytes: above this server's limit of 1000");
  refused(std::string("ok.obj\0x", 8), "NUL");
  refused(std::string(300, 'a'), "longer than");
  refused("", "empty");
  char* real = realpath(dir.c_str(), nullptr);
  ASSERT_NE(real, nullptr);
  const std::string ok = std::string(real) + "/ok.obj";
  std::free(real);
  EXPECT_EQ(ResolveSceneFile(dir, "ok.obj", 1000), ok);
  EXPECT_EQ(ResolveSceneFile(dir, "./ok.obj", 1000), ok);
}

}  // namespace
}  // namespace viscera::server
