#include "server/heartbeat_source.h"

#include <gtest/gtest.h>

#include <thread>

#include "bus/header.h"
#include "common/check.h"

namespace viscera::server {
namespace {

// Clocks the test sets by hand: the load is then an exact ratio, whatever the machine does.
struct FakeClocks {
  int64_t cpu = 5'000'000'000, wall = 7'000'000'000;
  HeartbeatClocks clocks() {
    return {[this] { return cpu; }, [this] { return wall; }};
  }
};

TEST(HeartbeatSource, CountsSequenceAndUptime) {
  FakeClocks t;
  HeartbeatSource source("s1", 5, t.clocks());
  const viscera_proto::heartbeat_t first = source.Next(2, 7);
  EXPECT_EQ(bus::HeaderProblem(first.header), "");
  EXPECT_EQ(first.header.seq, 0);
  EXPECT_EQ(first.header.session_id, 0);
  EXPECT_EQ(first.server_id, "s1");
  EXPECT_EQ(first.num_sessions, 2);
  EXPECT_EQ(first.max_sessions, 5);
  EXPECT_EQ(first.rejected, 7);
  EXPECT_EQ(first.uptime_us, 0);
  EXPECT_EQ(first.load, 0.0f);
  t.wall += 1'234'567'000;
  const viscera_proto::heartbeat_t second = source.Next(0);
  EXPECT_EQ(second.header.seq, 1);
  EXPECT_EQ(second.uptime_us, 1'234'567);
}

TEST(HeartbeatSource, LoadIsCpuTimeOverWallTimeSinceTheLastHeartbeat) {
  FakeClocks t;
  HeartbeatSource source("s1", 5, t.clocks());
  t.wall += 100'000'000;  // 100 ms with 150 ms of CPU: 1.5 cores
  t.cpu += 150'000'000;
  EXPECT_FLOAT_EQ(source.Next(0).load, 1.5f);
  t.wall += 200'000'000;  // then idle
  EXPECT_FLOAT_EQ(source.Next(0).load, 0.0f);
  t.wall += 50'000'000;  // only the time since the previous heartbeat counts
  t.cpu += 10'000'000;
  EXPECT_FLOAT_EQ(source.Next(0).load, 0.2f);
  t.wall += 500'000;  // under a millisecond apart: 0, not noise
  t.cpu += 500'000;
  EXPECT_EQ(source.Next(0).load, 0.0f);
}

// The real clocks, for liveness only: no rate on a shared machine is guaranteed.
TEST(HeartbeatSource, RealClocksGiveASaneLoad) {
  HeartbeatSource source("s1", 5);
  source.Next(0);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // wall time must pass: not a sync
  const viscera_proto::heartbeat_t next = source.Next(0);
  EXPECT_GE(next.uptime_us, 20'000);
  EXPECT_GE(next.load, 0.0f);
  EXPECT_LE(next.load, static_cast<float>(std::thread::hardware_concurrency()) + 0.1f);
}

TEST(HeartbeatSource, RejectsBadConfiguration) {
  EXPECT_THROW(HeartbeatSource("", 1), InputError);
  EXPECT_THROW(HeartbeatSource("s", 0), InputError);
}

}  // namespace
}  // namespace viscera::server
