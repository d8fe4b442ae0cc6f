// Placement: the ranking every client and server uses (bus::PickServer), the peers a full
// server names (PeerDirectory), and the default --max-sessions (capacity_estimate).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bus/header.h"
#include "bus/placement.h"
#include "common/check.h"
#include "server/capacity_estimate.h"
#include "server/peer_directory.h"

namespace viscera::server {
namespace {

using bus::ServerLoad;

std::string Picked(const std::vector<ServerLoad>& servers) {
  const auto best = bus::PickServer(servers);
  return best ? best->server_id : "none";
}

TEST(PickServer, LowerShareThenLowerLoadThenSmallerId) {
  EXPECT_EQ(Picked({{"a", 2, 4, 0.1}, {"b", 1, 4, 0.9}}), "b");  // share 1/4 < 2/4
  // 1/3 and 2/6 are the same share exactly (no rounding): the load decides, then the id
  EXPECT_EQ(Picked({{"a", 1, 3, 0.5}, {"b", 2, 6, 0.4}}), "b");
  EXPECT_EQ(Picked({{"b", 1, 3, 0.5}, {"a", 2, 6, 0.5}}), "a");
  // a big machine a quarter full beats a small one half full, whatever its load
  EXPECT_EQ(Picked({{"small", 1, 2, 0.0}, {"big", 4, 16, 3.0}}), "big");
}

TEST(PickServer, FullServersAreNeverPicked) {
  EXPECT_EQ(Picked({}), "none");
  EXPECT_EQ(Picked({{"a", 3, 3, 0.0}, {"b", 9, 4, 0.0}, {"c", 0, 0, 0.0}}), "none");
  EXPECT_EQ(Picked({{"a", 3, 3, 0.0}, {"z", 7, 8, 1.9}}), "z");
}

viscera_proto::heartbeat_t Heartbeat(const std::string& id, int sessions, int max) {
  viscera_proto::heartbeat_t hb;
  hb.header = bus::MakeHeader(0, 0);
  hb.server_id = id;
  hb.num_sessions = sessions;
  hb.max_sessions = max;
  hb.load = 0.0f;
  return hb;
}

TEST(PeerDirectory, SuggestsFreshPeersWithRoomNeverItself) {
  PeerDirectory peers("me", 3000);
  EXPECT_FALSE(peers.Suggest(0));
  peers.Observe(Heartbeat("me", 0, 10), 0);  // our own heartbeat comes back: not a peer
  EXPECT_FALSE(peers.Suggest(0));
  peers.Observe(Heartbeat("full", 2, 2), 0);
  EXPECT_FALSE(peers.Suggest(0));
  peers.Observe(Heartbeat("old", 0, 4), 0);
  peers.Observe(Heartbeat("new", 3, 4), 2000);
  EXPECT_EQ(peers.Suggest(2000)->server_id, "old");
  EXPECT_EQ(peers.Suggest(3500)->server_id, "new");  // "old" not heard for 3500 > 3000
  EXPECT_FALSE(peers.Suggest(6000));                 // nobody heard recently
  auto broken = Heartbeat("broken", 0, 4);
  broken.header.version = 1;  // another protocol version is not trusted
  peers.Observe(broken, 6000);
  EXPECT_FALSE(peers.Suggest(6000));
}

// Heartbeats with ever-new server ids grew the directory by 241 MB in 10 s: silent peers are
// forgotten and at most kMaxPeers are kept, a known peer still updates when it is full.
TEST(PeerDirectory, ForgetsSilentPeersAndIsCapped) {
  PeerDirectory peers("me", 3000);
  for (size_t i = 0; i < 10 * PeerDirectory::kMaxPeers; ++i) {
    std::string id = "p";  // appended: gcc 12's -Wrestrict misreads `"p" + std::string&&` at -O3
    id += std::to_string(i);
    peers.Observe(Heartbeat(id, 0, 4), 0);
  }
  EXPECT_EQ(peers.size(), PeerDirectory::kMaxPeers);
  peers.Observe(Heartbeat("p0", 4, 4), 1000);  // known: updated (now full)
  EXPECT_EQ(peers.size(), PeerDirectory::kMaxPeers);
  peers.Observe(Heartbeat("late", 0, 4), 1000);  // the directory is full of fresh peers: ignored
  EXPECT_EQ(peers.size(), PeerDirectory::kMaxPeers);
  peers.Observe(Heartbeat("later", 0, 4), 5000);  // every other peer is silent past 3000: forgotten
  EXPECT_EQ(peers.size(), 1u);
  EXPECT_EQ(peers.Suggest(5000)->server_id, "later");
}

TEST(CapacityEstimate, SessionsThatFitUseTheBudgetOfTheCores) {
  EXPECT_EQ(SessionsThatFit(2, 0.39), 3);  // 2 x 0.7 / 0.39 = 3.6
  EXPECT_EQ(SessionsThatFit(1, 0.35), 2);  // exactly 0.7 / 0.35
  EXPECT_EQ(SessionsThatFit(8, 0.05), 112);
  EXPECT_EQ(SessionsThatFit(1, 5.0), 1);  // at least one: the operator can still try
  EXPECT_EQ(SessionsThatFit(64, 1e-6), 1024);
  EXPECT_GE(AvailableCores(), 1);
}

TEST(CapacityEstimate, MeasuresTheSceneOnThisMachine) {
  ServerConfig config;
  config.scene_dir = std::string(VISCERA_SOURCE_DIR) + "/tests/e2e/scenes";
  config.frame_rate_hz = -1.0;  // mechanics only: no OSMesa in this test
  const CapacityEstimate e = EstimateCapacity(config, "push", 0.05);
  EXPECT_EQ(e.scene, "push");
  EXPECT_EQ(e.rate_hz, 100.0);  // the scene's own rate
  EXPECT_GT(e.step_cpu_us, 0.0);
  EXPECT_EQ(e.frame_cpu_ms, 0.0);
  EXPECT_DOUBLE_EQ(e.session_cores, e.step_cpu_us * 1e-6 * e.rate_hz);
  EXPECT_EQ(e.max_sessions, SessionsThatFit(e.cores, e.session_cores));
  EXPECT_NE(e.Describe().find("a push session costs"), std::string::npos) << e.Describe();
  // at ten times the rate, one session costs ten times as much (same step)
  config.rate_hz = 1000.0;
  EXPECT_EQ(EstimateCapacity(config, "push", 0.05).rate_hz, 1000.0);
  EXPECT_THROW(EstimateCapacity(config, "no_such_scene", 0.05), InputError);
}

// A stopping viscerad abandons its start-up measurement rather than wait for it (at nice 19 on a
// busy machine it ran for minutes): the stop is asked before and after loading the scene and
// before every step, and its first "yes" ends the measurement there.
TEST(CapacityEstimate, AStopAbandonsTheMeasurementAtTheNextStep) {
  ServerConfig config;
  config.scene_dir = std::string(VISCERA_SOURCE_DIR) + "/tests/e2e/scenes";
  config.frame_rate_hz = -1.0;
  for (const int stop_at : {1, 2, 3, 40}) {
    int asked = 0;
    // an hour of stepping unless the stop is heeded (ctest's timeout would fail the test)
    EXPECT_THROW(EstimateCapacity(config, "push", 3600.0, [&] { return ++asked >= stop_at; }),
                 MeasurementStopped);
    EXPECT_EQ(asked, stop_at) << "asked again after it said stop";
  }
}

// ... and before every frame, on the render thread.
TEST(CapacityEstimate, AStopAbandonsTheFramesToo) {
  ServerConfig config;
  config.scene_dir = std::string(VISCERA_SOURCE_DIR) + "/tests/e2e/scenes";
  config.frame_width = 160;
  config.frame_height = 120;
  ASSERT_GT(config.frame_rate_hz, 0.0);
  // no stepping time: the minimum steps (as many each time), then the frames
  auto checks = [&](const ServerConfig& c) {
    int asked = 0;
    EstimateCapacity(c, "push", 0.0, [&] {
      ++asked;
      return false;
    });
    return asked;
  };
  ServerConfig mechanics_only = config;
  mechanics_only.frame_rate_hz = -1.0;
  const int stepping = checks(mechanics_only), all = checks(config);
  EXPECT_GT(all, stepping + 1) << "the frames must ask too";
  for (const int stop_at : {stepping + 1, all}) {  // before the first frame, before the last
    int asked = 0;
    EXPECT_THROW(EstimateCapacity(config, "push", 0.0, [&] { return ++asked >= stop_at; }),
                 MeasurementStopped);
    EXPECT_EQ(asked, stop_at);
  }
}

}  // namespace
}  // namespace viscera::server
