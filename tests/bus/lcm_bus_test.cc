#include "bus/lcm_bus.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

#include <viscera_proto/heartbeat_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"

namespace viscera::bus {
namespace {

using viscera_proto::heartbeat_t;

// memq:// delivers only to subscribers of the same LCM object: a private, in-process bus.
constexpr char kMemq[] = "memq://";

heartbeat_t SampleHeartbeat(int64_t seq) {
  heartbeat_t msg;
  msg.header = MakeHeader(0, seq);
  msg.header.token = {0xde, 0xad, 0xbe, 0xef};
  msg.header.token_len = 4;
  msg.server_id = "test-server";
  msg.num_sessions = 3;
  msg.max_sessions = 8;
  msg.load = 0.25f;
  msg.uptime_us = 123'456'789;
  return msg;
}

void ExpectEqual(const heartbeat_t& a, const heartbeat_t& b) {
  EXPECT_EQ(a.header.version, b.header.version);
  EXPECT_EQ(a.header.session_id, b.header.session_id);
  EXPECT_EQ(a.header.seq, b.header.seq);
  EXPECT_EQ(a.header.utime, b.header.utime);
  EXPECT_EQ(a.header.token_len, b.header.token_len);
  EXPECT_EQ(a.header.token, b.header.token);
  EXPECT_EQ(a.server_id, b.server_id);
  EXPECT_EQ(a.num_sessions, b.num_sessions);
  EXPECT_EQ(a.max_sessions, b.max_sessions);
  EXPECT_EQ(a.load, b.load);  // float bits travel unchanged
  EXPECT_EQ(a.uptime_us, b.uptime_us);
}

TEST(LcmBus, HeartbeatRoundTripOverMemq) {
  LcmBus bus(kMemq);
  std::vector<heartbeat_t> got;
  int64_t recv_utime = 0;
  bus.Subscribe<heartbeat_t>(kHeartbeatChannel, [&](const heartbeat_t& msg, int64_t utime) {
    got.push_back(msg);
    recv_utime = utime;
  });
  const heartbeat_t sent = SampleHeartbeat(7);
  ASSERT_TRUE(bus.Publish(kHeartbeatChannel, sent));
  EXPECT_EQ(bus.Pump(1000), 1);
  ASSERT_EQ(got.size(), 1u);
  ExpectEqual(got[0], sent);
  EXPECT_EQ(HeaderProblem(got[0].header), "");
  EXPECT_GT(recv_utime, 0);
  const BusStats stats = bus.stats();
  EXPECT_EQ(stats.published, 1);
  EXPECT_EQ(stats.received, 1);
  EXPECT_EQ(stats.handled, 1);
  EXPECT_EQ(stats.decode_failures, 0);
}

TEST(LcmBus, DrainHandlesEveryQueuedMessage) {
  LcmBus bus(kMemq);
  std::vector<int64_t> seqs;
  bus.Subscribe<heartbeat_t>(
      kHeartbeatChannel, [&](const heartbeat_t& msg, int64_t) { seqs.push_back(msg.header.seq); });
  for (int64_t i = 0; i < 5; ++i) ASSERT_TRUE(bus.Publish(kHeartbeatChannel, SampleHeartbeat(i)));
  // handleTimeout handles one message per call; Drain must loop until none is left.
  EXPECT_EQ(bus.Drain(), 5);
  EXPECT_EQ(seqs, (std::vector<int64_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(bus.Drain(), 0);
}

// The flood bound (protocol.md, Bad input): one Drain handles at most max_messages, so a
// flood cannot keep the I/O thread in one pump forever; the rest waits for the next pump.
TEST(LcmBus, DrainHandlesAtMostItsBound) {
  LcmBus bus(kMemq);
  int handled = 0;
  bus.Subscribe<heartbeat_t>(kHeartbeatChannel, [&](const heartbeat_t&, int64_t) { ++handled; });
  for (int64_t i = 0; i < 12; ++i) ASSERT_TRUE(bus.Publish(kHeartbeatChannel, SampleHeartbeat(i)));
  EXPECT_EQ(bus.Drain(10), 10);
  EXPECT_EQ(handled, 10);
  EXPECT_EQ(bus.Drain(10), 2);
  EXPECT_EQ(handled, 12);
}

TEST(LcmBus, MalformedDatagramsAreCountedAndLaterMessagesArrive) {
  LcmBus bus(kMemq);
  std::vector<heartbeat_t> got;
  bus.Subscribe<heartbeat_t>(kHeartbeatChannel,
                             [&](const heartbeat_t& msg, int64_t) { got.push_back(msg); });

  // Garbage bytes (fixed seed), a truncated heartbeat, a heartbeat with a trailing
  // byte, a message of another type, and an empty datagram.
  std::mt19937 rng(42);
  std::vector<uint8_t> garbage(200);
  for (auto& b : garbage) b = static_cast<uint8_t>(rng());
  ASSERT_TRUE(bus.PublishRaw(kHeartbeatChannel, garbage.data(), static_cast<int>(garbage.size())));

  const heartbeat_t good = SampleHeartbeat(1);
  std::vector<uint8_t> encoded(static_cast<size_t>(good.getEncodedSize()));
  ASSERT_EQ(good.encode(encoded.data(), 0, static_cast<int>(encoded.size())),
            static_cast<int>(encoded.size()));
  ASSERT_TRUE(
      bus.PublishRaw(kHeartbeatChannel, encoded.data(), static_cast<int>(encoded.size()) - 3));
  encoded.push_back(0);
  ASSERT_TRUE(bus.PublishRaw(kHeartbeatChannel, encoded.data(), static_cast<int>(encoded.size())));

  ASSERT_TRUE(bus.Publish(kHeartbeatChannel, MakeHeader(0, 0)));
  ASSERT_TRUE(bus.PublishRaw(kHeartbeatChannel, encoded.data(), 0));

  ASSERT_TRUE(bus.Publish(kHeartbeatChannel, good));
  EXPECT_EQ(bus.Drain(), 6);

  ASSERT_EQ(got.size(), 1u);
  ExpectEqual(got[0], good);
  const BusStats stats = bus.stats();
  EXPECT_EQ(stats.decode_failures, 5);
  EXPECT_EQ(stats.handled, 1);
  EXPECT_NE(bus.last_error().find("malformed"), std::string::npos) << bus.last_error();
}

TEST(LcmBus, ThrowingHandlerIsCountedAndTheBusLivesOn) {
  LcmBus bus(kMemq);
  int calls = 0;
  bus.Subscribe<heartbeat_t>(kHeartbeatChannel, [&](const heartbeat_t& msg, int64_t) {
    ++calls;
    if (msg.header.seq == 0) throw std::runtime_error("boom");
    if (msg.header.seq == 1) throw 17;  // not even a std::exception
  });
  for (int64_t i = 0; i < 3; ++i) ASSERT_TRUE(bus.Publish(kHeartbeatChannel, SampleHeartbeat(i)));
  EXPECT_EQ(bus.Drain(), 3);
  EXPECT_EQ(calls, 3);
  const BusStats stats = bus.stats();
  EXPECT_EQ(stats.handler_failures, 2);
  EXPECT_EQ(stats.handled, 1);
  EXPECT_EQ(stats.decode_failures, 0);
}

TEST(LcmBus, UnsubscribeInsideAHandlerIsDeferred) {
  LcmBus bus(kMemq);
  int calls = 0;
  SubscriptionId id = 0;
  id = bus.Subscribe<heartbeat_t>(kHeartbeatChannel, [&](const heartbeat_t&, int64_t) {
    ++calls;
    bus.Unsubscribe(id);
  });
  ASSERT_TRUE(bus.Publish(kHeartbeatChannel, SampleHeartbeat(0)));
  ASSERT_TRUE(bus.Publish(kHeartbeatChannel, SampleHeartbeat(1)));
  bus.Drain();
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(bus.stats().handler_failures, 0);
}

TEST(LcmBus, PublishFromAnotherThreadWhileTheOwnerPumps) {
  LcmBus bus(kMemq);
  constexpr int kCount = 200;
  std::vector<int64_t> seqs;
  bus.Subscribe<heartbeat_t>(
      kHeartbeatChannel, [&](const heartbeat_t& msg, int64_t) { seqs.push_back(msg.header.seq); });
  std::thread publisher([&] {
    for (int64_t i = 0; i < kCount; ++i) bus.Publish(kHeartbeatChannel, SampleHeartbeat(i));
  });
  // 5 s is far beyond need: the loop ends as soon as everything has arrived
  for (int i = 0; i < 500 && static_cast<int>(seqs.size()) < kCount; ++i) bus.Pump(10);
  publisher.join();
  bus.Drain();
  ASSERT_EQ(static_cast<int>(seqs.size()), kCount);
  for (int i = 0; i < kCount; ++i) EXPECT_EQ(seqs[i], i);  // one publisher: order kept
  EXPECT_EQ(bus.stats().published, kCount);
}

TEST(LcmBus, PumpTimesOutWhenNothingArrives) {
  LcmBus bus(kMemq);
  bus.Subscribe<heartbeat_t>(kHeartbeatChannel, [](const heartbeat_t&, int64_t) {});
  EXPECT_EQ(bus.Pump(20), 0);
  EXPECT_THROW(bus.Pump(-1), InputError);
}

TEST(LcmBus, BadUrlThrows) { EXPECT_THROW(LcmBus("nosuchprovider://x"), InputError); }

TEST(LcmBus, HeaderProblemNamesTheFault) {
  viscera_proto::header_t header = MakeHeader(5, 0);
  EXPECT_EQ(HeaderProblem(header), "");
  header.token_len = 2;
  EXPECT_NE(HeaderProblem(header).find("token_len"), std::string::npos);
  header = MakeHeader(5, 0);
  header.version = 99;
  EXPECT_NE(HeaderProblem(header).find("version 99"), std::string::npos);
}

TEST(ResolveUrl, FlagThenEnvironmentThenDefault) {
  ::unsetenv("LCM_DEFAULT_URL");
  EXPECT_EQ(ResolveUrl(""), kDefaultUrl);
  ::setenv("LCM_DEFAULT_URL", "memq://", 1);
  EXPECT_EQ(ResolveUrl(""), "memq://");
  EXPECT_EQ(ResolveUrl("udpm://239.255.76.67:7668?ttl=0"), "udpm://239.255.76.67:7668?ttl=0");
  ::unsetenv("LCM_DEFAULT_URL");
}

// The off-loopback check reads every ttl: LCM takes the last of repeated options, and the
// check took the first ("?ttl=0&ttl=1" started without a key and sent with TTL 1).
TEST(UrlLeavesHost, EveryTtlCountsNotOnlyTheFirst) {
  EXPECT_FALSE(UrlLeavesHost("udpm://239.255.76.67:7667?ttl=0"));
  EXPECT_FALSE(UrlLeavesHost("udpm://239.255.76.67:7667?ttl=00&recv_buf_size=100"));
  EXPECT_FALSE(UrlLeavesHost("memq://"));
  EXPECT_TRUE(UrlLeavesHost("udpm://239.255.76.67:7667?ttl=1"));
  EXPECT_TRUE(UrlLeavesHost("udpm://239.255.76.67:7667?ttl=0&ttl=1"));
  EXPECT_TRUE(UrlLeavesHost("udpm://239.255.76.67:7667?ttl=1&ttl=0"));
  EXPECT_TRUE(UrlLeavesHost("udpm://239.255.76.67:7667?ttl="));
  EXPECT_TRUE(UrlLeavesHost("tcpq://127.0.0.1:7700"));
}

}  // namespace
}  // namespace viscera::bus
