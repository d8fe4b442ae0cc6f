#include "bus/message_auth.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <viscera_proto/heartbeat_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/lcm_bus.h"
#include "common/check.h"

namespace viscera::bus {
namespace {

MessageAuth::Key KeyOf(uint8_t fill) {
  MessageAuth::Key key;
  key.fill(fill);
  return key;
}

std::vector<uint8_t> Encoded(const viscera_proto::heartbeat_t& msg) {
  std::vector<uint8_t> out(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(out.data(), 0, static_cast<int>(out.size()));
  return out;
}

viscera_proto::heartbeat_t Beat() {
  viscera_proto::heartbeat_t msg;
  msg.header = MakeHeader(0, 3);
  msg.header.token = {1, 2, 3, 4, 5};
  msg.header.token_len = 5;
  msg.server_id = "s";
  msg.num_sessions = 1;
  msg.max_sessions = 2;
  msg.load = 0.5f;
  msg.uptime_us = 9;
  msg.rejected = 0;
  return msg;
}

TEST(MessageAuth, SignedMessageVerifiesAndStillDecodes) {
  const MessageAuth auth(KeyOf(7));
  std::vector<uint8_t> bytes = Encoded(Beat());
  const size_t unsigned_size = bytes.size();
  ASSERT_TRUE(auth.Sign(&bytes));
  EXPECT_EQ(bytes.size(), unsigned_size + kMacBytes);
  std::vector<uint8_t> scratch;
  EXPECT_TRUE(auth.Verify(bytes.data(), static_cast<int>(bytes.size()), &scratch));
  // the signed datagram is an ordinary message whose header carries the MAC
  viscera_proto::heartbeat_t decoded;
  ASSERT_EQ(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  EXPECT_EQ(decoded.header.mac_len, kMacBytes);
  EXPECT_EQ(decoded.header.token, (std::vector<uint8_t>{1, 2, 3, 4, 5}));
  EXPECT_EQ(decoded.server_id, "s");
  EXPECT_EQ(HeaderProblem(decoded.header), "");
}

TEST(MessageAuth, EveryFlippedByteAnotherKeyOrNoMacFails) {
  const MessageAuth auth(KeyOf(7));
  std::vector<uint8_t> bytes = Encoded(Beat());
  const std::vector<uint8_t> plain = bytes;
  ASSERT_TRUE(auth.Sign(&bytes));
  std::vector<uint8_t> scratch;
  for (size_t i = 0; i < bytes.size(); ++i) {
    std::vector<uint8_t> tampered = bytes;
    tampered[i] ^= 0x01;
    EXPECT_FALSE(auth.Verify(tampered.data(), static_cast<int>(tampered.size()), &scratch))
        << "flipped byte " << i;
  }
  EXPECT_FALSE(
      MessageAuth(KeyOf(8)).Verify(bytes.data(), static_cast<int>(bytes.size()), &scratch));
  EXPECT_FALSE(auth.Verify(plain.data(), static_cast<int>(plain.size()), &scratch));
  // truncated and garbage datagrams are simply not authentic
  EXPECT_FALSE(auth.Verify(bytes.data(), 20, &scratch));
  const std::vector<uint8_t> garbage(100, 0xff);
  EXPECT_FALSE(auth.Verify(garbage.data(), static_cast<int>(garbage.size()), &scratch));
  std::vector<uint8_t> not_viscera(5, 0);
  EXPECT_FALSE(auth.Sign(&not_viscera));
  // signing twice is refused: the MAC field is already taken
  EXPECT_FALSE(auth.Sign(&bytes));
}

TEST(MessageAuth, KeyFilesRoundTripAndShortFilesAreRefused) {
  const std::string path = ::testing::TempDir() + "/viscera_key_test.key";
  MessageAuth::WriteKeyFile(path);
  std::vector<uint8_t> bytes = Encoded(Beat());
  ASSERT_TRUE(MessageAuth::FromKeyFile(path).Sign(&bytes));
  std::vector<uint8_t> scratch;
  EXPECT_TRUE(MessageAuth::FromKeyFile(path).Verify(bytes.data(), static_cast<int>(bytes.size()),
                                                    &scratch));
  MessageAuth::WriteKeyFile(path);  // a new key: the old MAC no longer verifies
  EXPECT_FALSE(MessageAuth::FromKeyFile(path).Verify(bytes.data(), static_cast<int>(bytes.size()),
                                                     &scratch));
  std::ofstream(path, std::ios::trunc) << "short";
  EXPECT_THROW(MessageAuth::FromKeyFile(path), InputError);
  std::remove(path.c_str());
  EXPECT_THROW(MessageAuth::FromKeyFile(path), InputError);
}

TEST(MessageAuth, BusWithAKeyDropsUnsignedDatagramsAndCountsThem) {
  LcmBus bus("memq://");
  bus.SetAuth(std::make_shared<MessageAuth>(KeyOf(3)));
  int handled = 0;
  std::vector<DropReason> drops;
  bus.SetDropHandler([&](const std::string& channel, DropReason reason, const uint8_t*, int) {
    EXPECT_EQ(channel, kHeartbeatChannel);
    drops.push_back(reason);
  });
  bus.Subscribe<viscera_proto::heartbeat_t>(
      kHeartbeatChannel, [&](const viscera_proto::heartbeat_t&, int64_t) { ++handled; });
  ASSERT_TRUE(bus.Publish(kHeartbeatChannel, Beat()));  // signed by the bus
  const std::vector<uint8_t> forged = Encoded(Beat());  // same content, no MAC
  ASSERT_TRUE(bus.PublishRaw(kHeartbeatChannel, forged.data(), static_cast<int>(forged.size())));
  bus.Pump(100);
  bus.Drain();
  EXPECT_EQ(handled, 1);
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_EQ(drops[0], DropReason::kBadMac);
  EXPECT_EQ(bus.stats().auth_failures, 1);
}

TEST(SecureEquals, ComparesContentAndSize) {
  EXPECT_TRUE(SecureEquals({1, 2, 3}, {1, 2, 3}));
  EXPECT_FALSE(SecureEquals({1, 2, 3}, {1, 2, 4}));
  EXPECT_FALSE(SecureEquals({1, 2, 3}, {1, 2}));
  EXPECT_FALSE(SecureEquals({}, {1}));
  EXPECT_EQ(RandomBytes(16).size(), 16u);
  EXPECT_NE(RandomBytes(16), RandomBytes(16));  // 2^-128 chance of a false failure
}

// LCM 1.3.1's decode sizes an array before checking its bytes: a datagram claiming a 2 GB
// token must be dropped before decoding, not allocate 2 GB (found by fuzz_server_messages).
TEST(HeaderCountsFit, RefusesCountsBeyondTheDatagramBeforeDecoding) {
  viscera_proto::heartbeat_t hb{};
  hb.header = MakeHeader(0, 0);
  std::vector<uint8_t> bytes(static_cast<size_t>(hb.getEncodedSize()));
  ASSERT_EQ(hb.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  EXPECT_TRUE(HeaderCountsFit(bytes.data(), static_cast<int>(bytes.size())));
  const int token_len_at = MacLenOffset(bytes.data(), static_cast<int>(bytes.size())) - 4;
  std::vector<uint8_t> huge_token = bytes;
  for (int i = 0; i < 4; ++i)
    huge_token[static_cast<size_t>(token_len_at + i)] = i == 0 ? 0x7f : 0xff;
  EXPECT_FALSE(HeaderCountsFit(huge_token.data(), static_cast<int>(huge_token.size())));
  std::vector<uint8_t> huge_mac = bytes;
  const int mac_len_at = MacLenOffset(bytes.data(), static_cast<int>(bytes.size()));
  for (int i = 0; i < 4; ++i) huge_mac[static_cast<size_t>(mac_len_at + i)] = i == 0 ? 0x7f : 0xff;
  EXPECT_FALSE(HeaderCountsFit(huge_mac.data(), static_cast<int>(huge_mac.size())));

  // through the bus: dropped as malformed, never handed on
  LcmBus bus("memq://");
  int handled = 0, malformed = 0;
  bus.Subscribe<viscera_proto::heartbeat_t>(
      kHeartbeatChannel, [&](const viscera_proto::heartbeat_t&, int64_t) { ++handled; });
  bus.SetDropHandler([&](const std::string&, DropReason reason, const uint8_t*, int) {
    malformed += reason == DropReason::kMalformed ? 1 : 0;
  });
  bus.PublishRaw(kHeartbeatChannel, huge_token.data(), static_cast<int>(huge_token.size()));
  bus.PublishRaw(kHeartbeatChannel, bytes.data(), static_cast<int>(bytes.size()));
  bus.Drain();
  EXPECT_EQ(handled, 1);
  EXPECT_EQ(malformed, 1);
}

}  // namespace
}  // namespace viscera::bus
