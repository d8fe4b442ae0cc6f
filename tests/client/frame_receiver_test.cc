// The frame stream's accounting on an in-process bus: what arrives, what was lost on the way
// (sequence gaps), what the server dropped, and what is refused (stale, another session or
// version, empty), each counted exactly.
#include "client/frame_receiver.h"

#include <gtest/gtest.h>

#include <vector>

#include "bus/channels.h"
#include "bus/header.h"

namespace viscera::client {
namespace {

constexpr int64_t kId = 7;

viscera_proto::jpeg_frame_t Frame(int64_t seq, int64_t dropped, int64_t session = kId) {
  viscera_proto::jpeg_frame_t f{};
  f.header = bus::MakeHeader(session, seq);
  f.dropped = dropped;
  f.width = 4;
  f.height = 2;
  f.data = {0xff, 0xd8, 0xff, 0xd9};
  f.size = static_cast<int32_t>(f.data.size());
  f.snapshot_utime = f.header.utime - 1000 * (seq + 1);  // ages of 1, 2, ... ms
  return f;
}

TEST(FrameReceiver, CountsLostDroppedAndRejectedFramesExactly) {
  bus::LcmBus bus("memq://");
  std::vector<int64_t> handed_on;
  FrameReceiver receiver(
      &bus, kId, [&](const viscera_proto::jpeg_frame_t& f) { handed_on.push_back(f.header.seq); });
  const std::string channel = bus::SessionChannel(bus::kFramePrefix, kId);
  // the server's renderer dropped 2 frames between seq 0 and seq 6; 2, 4, 5 never arrive
  // in order (2 comes late, after 3), and another session's frame is on this channel
  bus.Publish(channel, Frame(0, 10));
  bus.Publish(channel, Frame(1, 10));
  bus.Publish(channel, Frame(3, 11));
  bus.Publish(channel, Frame(2, 11));  // stale: after 3
  bus.Publish(channel, Frame(9, 11, /*session=*/kId + 1));
  bus.Publish(channel, Frame(6, 12));
  bus.Drain();

  EXPECT_EQ(handed_on, (std::vector<int64_t>{0, 1, 3, 6}));
  const FrameStreamStats s = receiver.stats();
  EXPECT_EQ(s.received, 4);
  EXPECT_EQ(s.lost, 3);  // 2 (came too late to count), 4 and 5
  EXPECT_EQ(s.server_dropped, 2);
  EXPECT_EQ(receiver.rejected(), 2);
  EXPECT_EQ(s.bytes, 16);
  EXPECT_NE(receiver.last_rejection().find("session 8"), std::string::npos)
      << receiver.last_rejection();
  // every frame the server rendered or skipped since the first one is accounted for
  EXPECT_EQ(s.received + s.lost + s.server_dropped, 6 + 1 + 2);
  EXPECT_GE(s.age_p50_ms, 1.0);
}

TEST(FrameReceiver, RefusesOtherVersionsEmptyFramesAndReplays) {
  bus::LcmBus bus("memq://");
  int handed_on = 0;
  FrameReceiver receiver(&bus, kId, [&](const viscera_proto::jpeg_frame_t&) { ++handed_on; });
  const std::string channel = bus::SessionChannel(bus::kFramePrefix, kId);
  auto other_version = Frame(0, 0);
  other_version.header.version = viscera_proto::header_t::kProtocolVersion + 1;
  bus.Publish(channel, other_version);
  bus.Drain();
  EXPECT_NE(receiver.last_rejection().find("protocol version"), std::string::npos)
      << receiver.last_rejection();
  auto empty = Frame(1, 0);
  empty.data.clear();
  empty.size = 0;
  bus.Publish(channel, empty);
  bus.Drain();
  EXPECT_NE(receiver.last_rejection().find("0 bytes"), std::string::npos)
      << receiver.last_rejection();
  bus.Publish(channel, Frame(5, 0));
  bus.Publish(channel, Frame(5, 0));  // the same frame again
  bus.Drain();
  EXPECT_NE(receiver.last_rejection().find("frame 5 after frame 5"), std::string::npos)
      << receiver.last_rejection();
  EXPECT_EQ(handed_on, 1);
  EXPECT_EQ(receiver.received(), 1);
  EXPECT_EQ(receiver.rejected(), 3);
  EXPECT_EQ(receiver.stats().lost, 0);  // the first frame received starts the count
}

}  // namespace
}  // namespace viscera::client
