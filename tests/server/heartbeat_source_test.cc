#include "server/heartbeat_source.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "bus/header.h"
#include "common/check.h"

namespace viscera::server {
namespace {

TEST(HeartbeatSource, CountsSequenceAndUptimeAndMeasuresLoad) {
  HeartbeatSource source("s1", 5);
  const viscera_proto::heartbeat_t first = source.Next(2);
  EXPECT_EQ(bus::HeaderProblem(first.header), "");
  EXPECT_EQ(first.header.seq, 0);
  EXPECT_EQ(first.header.session_id, 0);
  EXPECT_EQ(first.server_id, "s1");
  EXPECT_EQ(first.num_sessions, 2);
  EXPECT_EQ(first.max_sessions, 5);

  // burn ~50 ms of CPU: the load over that period must be near one core
  const auto start = std::chrono::steady_clock::now();
  volatile double sink = 0.0;
  while (std::chrono::steady_clock::now() - start < std::chrono::milliseconds(50)) sink = sink + 1.0;
  const viscera_proto::heartbeat_t busy = source.Next(0);
  EXPECT_EQ(busy.header.seq, 1);
  EXPECT_GT(busy.uptime_us, first.uptime_us + 49'000);
  // loose bounds: on a loaded 2-core machine this thread may be preempted
  EXPECT_GT(busy.load, 0.3f);
  EXPECT_LT(busy.load, 2.1f);

  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const viscera_proto::heartbeat_t idle = source.Next(0);
  EXPECT_LT(idle.load, 0.3f);
}

TEST(HeartbeatSource, RejectsBadConfiguration) {
  EXPECT_THROW(HeartbeatSource("", 1), InputError);
  EXPECT_THROW(HeartbeatSource("s", 0), InputError);
}

}  // namespace
}  // namespace viscera::server
