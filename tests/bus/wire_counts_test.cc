#include "bus/wire_counts.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <viscera_proto/heartbeat_t.hpp>
#include <viscera_proto/jpeg_frame_t.hpp>
#include <viscera_proto/session_reply_t.hpp>
#include <viscera_proto/session_status_t.hpp>
#include <viscera_proto/skeleton_state_t.hpp>
#include <viscera_proto/step_record_t.hpp>

#include "bus/header.h"
#include "bus/lcm_bus.h"

namespace viscera::bus {
namespace {

// The process's peak resident memory so far, in MB.
int64_t PeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024;
}

template <typename Msg>
std::vector<uint8_t> Encode(const Msg& msg) {
  std::vector<uint8_t> bytes(static_cast<size_t>(msg.getEncodedSize()));
  EXPECT_EQ(msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  return bytes;
}

std::vector<uint8_t> BigEndian(int32_t v) {
  const auto u = static_cast<uint32_t>(v);
  return {static_cast<uint8_t>(u >> 24), static_cast<uint8_t>(u >> 16),
          static_cast<uint8_t>(u >> 8), static_cast<uint8_t>(u)};
}

// `bytes` with the one occurrence of `from` (the encoding of a count the test chose to be
// unique in the message) replaced by `to`.
std::vector<uint8_t> Patched(std::vector<uint8_t> bytes, const std::vector<uint8_t>& from,
                             const std::vector<uint8_t>& to) {
  std::vector<size_t> at;
  for (size_t i = 0; i + from.size() <= bytes.size(); ++i) {
    if (std::equal(from.begin(), from.end(), bytes.begin() + static_cast<std::ptrdiff_t>(i)))
      at.push_back(i);
  }
  EXPECT_EQ(at.size(), 1u) << "the count to patch is not unique in the encoding: " << int{from[3]};
  if (at.size() == 1)
    std::copy(to.begin(), to.end(), bytes.begin() + static_cast<std::ptrdiff_t>(at[0]));
  return bytes;
}

template <typename Msg>
bool Fits(const std::vector<uint8_t>& bytes) {
  return ArrayCountsFit<Msg>(bytes.data(), static_cast<int>(bytes.size()));
}

// Every honest message fits; the same message claiming 2^31 - 1 or -1 elements does not.
template <typename Msg>
void ExpectRefusesHostileCounts(const Msg& msg, int32_t count) {
  const auto bytes = Encode(msg);
  EXPECT_TRUE(Fits<Msg>(bytes)) << Msg::getTypeName();
  EXPECT_FALSE(Fits<Msg>(Patched(bytes, BigEndian(count), BigEndian(0x7fffffff))))
      << Msg::getTypeName();
  EXPECT_FALSE(Fits<Msg>(Patched(bytes, BigEndian(count), BigEndian(-1)))) << Msg::getTypeName();
  EXPECT_FALSE(Fits<Msg>(Patched(bytes, BigEndian(count), BigEndian(count + 1))))
      << Msg::getTypeName();
  // every truncation of an honest message is refused too (the walk never reads past the end)
  for (size_t cut = 0; cut < bytes.size(); ++cut) {
    const std::vector<uint8_t> part(bytes.begin(),
                                    bytes.begin() + static_cast<std::ptrdiff_t>(cut));
    if (Fits<Msg>(part)) {
      // only a cut inside the trailing fixed fields may pass the count walk; decode refuses it
      Msg decoded;
      EXPECT_LT(decoded.decode(part.data(), 0, static_cast<int>(part.size())), 0)
          << Msg::getTypeName() << " cut " << cut;
    }
  }
}

viscera_proto::session_status_t Status(int tools) {
  viscera_proto::session_status_t s{};
  s.header = MakeHeader(0, 0);
  s.num_tools = tools;
  s.tool_names.assign(static_cast<size_t>(tools), "t");
  const size_t n = static_cast<size_t>(tools);
  for (std::vector<double>* v : {&s.tool_path_length, &s.tool_active_time, &s.tool_force_p50,
                                 &s.tool_force_p95, &s.tool_force_max, &s.tool_contact_time,
                                 &s.tool_traction_time, &s.tool_organ_contact_time}) {
    v->assign(n, 0.5);
  }
  for (std::vector<int32_t>* v :
       {&s.tool_traction_events, &s.tool_grasps, &s.tool_regrasps, &s.tool_organ_contacts}) {
    v->assign(n, 12345);
  }
  return s;
}

TEST(ArrayCountsFit, RefusesEveryArrayCountBeyondTheDatagram) {
  viscera_proto::jpeg_frame_t frame{};
  frame.header = MakeHeader(0, 0);
  frame.size = 37;
  frame.data.assign(37, 0x11);
  ExpectRefusesHostileCounts(frame, 37);

  viscera_proto::skeleton_state_t skeleton{};
  skeleton.header = MakeHeader(0, 0);
  skeleton.num_points = 77;
  skeleton.points.assign(77, {0.0, 0.0, 0.0});
  ExpectRefusesHostileCounts(skeleton, 77);
  skeleton.num_spheres = 66;
  skeleton.spheres.assign(66, {0.0, 0.0, 0.0});
  ExpectRefusesHostileCounts(skeleton, 66);

  ExpectRefusesHostileCounts(Status(29), 29);

  viscera_proto::session_reply_t reply{};
  reply.header = MakeHeader(0, 0);
  reply.num_sessions =
      7;  // not 5 or 6: protocol version 5 and utime's top bytes 00 06 follow zeros
  reply.sessions.assign(7, Status(0));
  ExpectRefusesHostileCounts(reply, 7);
  reply.sessions[3] = Status(23);  // a status's tool names inside a reply
  ExpectRefusesHostileCounts(reply, 23);

  viscera_proto::step_record_t record{};
  record.header = MakeHeader(0, 0);
  record.num_tools = 9;
  record.tools.assign(9, viscera_proto::tool_target_t{});
  ExpectRefusesHostileCounts(record, 9);
}

// The counters appended at the end of session_status_t, inside a reply of several statuses: the
// walk must step over every one of them (a walk that misses one reads the next status from the
// wrong place and refuses every honest reply of two or more), and they decode intact.
TEST(ArrayCountsFit, AReplysStatusesKeepTheirLastCounters) {
  viscera_proto::session_reply_t reply{};
  reply.header = MakeHeader(0, 0);
  reply.num_sessions = 3;
  for (int i = 0; i < 3; ++i) {
    viscera_proto::session_status_t s = Status(i + 1);
    s.messages_dropped = 11 + i;
    s.nonfinite_dropped = 21 + i;
    s.record_failures = 31 + i;
    s.unconverged_solves = (int64_t{1} << 40) + i;
    reply.sessions.push_back(s);
  }
  const auto bytes = Encode(reply);
  ASSERT_TRUE(Fits<viscera_proto::session_reply_t>(bytes));
  EXPECT_TRUE(CountsFitForFingerprint(bytes.data(), static_cast<int>(bytes.size())));
  viscera_proto::session_reply_t decoded;
  ASSERT_EQ(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  ASSERT_EQ(decoded.sessions.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(decoded.sessions[i].num_tools, i + 1);
    EXPECT_EQ(decoded.sessions[i].record_failures, 31 + i);
    EXPECT_EQ(decoded.sessions[i].unconverged_solves, (int64_t{1} << 40) + i);
  }
  // a status on its own: its walk ends exactly at the end (a byte more or less is refused)
  const auto status = Encode(reply.sessions[2]);
  EXPECT_TRUE(Fits<viscera_proto::session_status_t>(status));
  const std::vector<uint8_t> short_by_one(status.begin(), status.end() - 1);
  EXPECT_FALSE(Fits<viscera_proto::session_status_t>(short_by_one));
}

// A status carrying running the bowel's score: `missed` segments not inspected, `events`
// damage events, `damaged` segments and `failed` pass marks (each count chosen unique in the
// encoding).
viscera_proto::session_status_t RunningStatus(int missed, int events, int damaged, int failed) {
  viscera_proto::session_status_t s = Status(2);
  s.running_segments = 90;
  s.running_num_missed = missed;
  for (int i = 0; i < missed; ++i) s.running_missed.push_back(1000 + i);
  s.running_num_events = events;
  for (int i = 0; i < events; ++i) {
    s.running_event_kinds.push_back("pinch");
    s.running_event_segments.push_back(2000 + i);
    s.running_event_tools.push_back("left");
    s.running_event_times.push_back(1.5);
    s.running_event_values.push_back(20.0);
  }
  s.running_num_damaged = damaged;
  for (int i = 0; i < damaged; ++i) s.running_damaged.push_back(3000 + i);
  s.running_num_failed = failed;
  s.running_failed.assign(static_cast<size_t>(failed), "damage");
  s.running_pass_damage_events = 4000;
  return s;
}

TEST(ArrayCountsFit, RefusesHostileCountsOfTheRunningScore) {
  ExpectRefusesHostileCounts(RunningStatus(41, 1, 1, 1), 41);
  ExpectRefusesHostileCounts(RunningStatus(1, 43, 1, 1), 43);
  ExpectRefusesHostileCounts(RunningStatus(1, 1, 47, 1), 47);
  ExpectRefusesHostileCounts(RunningStatus(1, 1, 1, 53), 53);
  // inside a reply, between two statuses: the walk steps over every running field
  viscera_proto::session_reply_t reply{};
  reply.header = MakeHeader(0, 0);
  reply.num_sessions = 2;
  reply.sessions = {RunningStatus(41, 3, 1, 2), RunningStatus(37, 1, 1, 1)};
  const auto bytes = Encode(reply);
  ASSERT_TRUE(Fits<viscera_proto::session_reply_t>(bytes));
  viscera_proto::session_reply_t decoded;
  ASSERT_EQ(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  EXPECT_EQ(decoded.sessions[0].running_event_segments, (std::vector<int32_t>{2000, 2001, 2002}));
  EXPECT_EQ(decoded.sessions[1].running_num_missed, 37);
  EXPECT_EQ(decoded.sessions[1].running_pass_damage_events, 4000);
  ExpectRefusesHostileCounts(reply, 37);
}

// LCM's string decode assigns length - 1 bytes: a zero length would ask for SIZE_MAX.
TEST(ArrayCountsFit, RefusesAStringWithoutItsTerminator) {
  viscera_proto::heartbeat_t hb{};
  hb.header = MakeHeader(0, 0);
  hb.server_id = "x";
  const auto bytes = Encode(hb);
  EXPECT_TRUE(Fits<viscera_proto::heartbeat_t>(bytes));
  EXPECT_FALSE(
      Fits<viscera_proto::heartbeat_t>(Patched(bytes, {0, 0, 0, 2, 'x', 0}, {0, 0, 0, 0, 'x', 0})));
  EXPECT_FALSE(Fits<viscera_proto::heartbeat_t>(
      Patched(bytes, {0, 0, 0, 2, 'x', 0}, {0xff, 0xff, 0xff, 0xfe, 'x', 0})));
}

// A string after the fixed fields (a heartbeat's capacity) is walked too: its length of -2^31
// made the generated decode compute length - 1 in int32 (a signed overflow, caught by fuzzing).
TEST(ArrayCountsFit, RefusesAHostileLengthOfAStringAfterTheFixedFields) {
  viscera_proto::heartbeat_t hb{};
  hb.header = MakeHeader(0, 0);
  hb.server_id = "x";
  hb.capacity = "cap";
  const auto bytes = Encode(hb);
  EXPECT_TRUE(Fits<viscera_proto::heartbeat_t>(bytes));
  const std::vector<uint8_t> capacity = {0, 0, 0, 4, 'c', 'a', 'p', 0};
  for (const int32_t length : {std::numeric_limits<int32_t>::min(), -1, 0, 5, 0x7fffffff}) {
    std::vector<uint8_t> hostile = BigEndian(length);
    hostile.insert(hostile.end(), capacity.begin() + 4, capacity.end());
    EXPECT_FALSE(Fits<viscera_proto::heartbeat_t>(Patched(bytes, capacity, hostile))) << length;
  }
}

// Through a client's bus: a 60-odd-byte frame datagram claiming 2 GB of JPEG is dropped as
// malformed, and the process's peak memory does not move (without the check, LCM's decode
// allocates and zeroes the 2 GB: the peak jumps by that much).
TEST(ArrayCountsFit, AHostileFrameIsDroppedWithoutALargeAllocation) {
  viscera_proto::jpeg_frame_t frame{};
  frame.header = MakeHeader(0, 0);
  frame.size = 37;
  frame.data.assign(37, 0x11);
  const auto hostile = Patched(Encode(frame), BigEndian(37), BigEndian(0x7fffffff));
  const auto honest = Encode(frame);

  LcmBus bus("memq://");
  int handled = 0;
  bus.Subscribe<viscera_proto::jpeg_frame_t>(
      "VISCERA_FRAME_1", [&](const viscera_proto::jpeg_frame_t&, int64_t) { ++handled; });
  const int64_t peak_before = PeakRssMb();
  bus.PublishRaw("VISCERA_FRAME_1", hostile.data(), static_cast<int>(hostile.size()));
  bus.Drain();
  EXPECT_EQ(handled, 0);
  EXPECT_EQ(bus.stats().decode_failures, 1);
  EXPECT_LT(PeakRssMb() - peak_before, 64) << "a hostile count reached the decoder";

  bus.PublishRaw("VISCERA_FRAME_1", honest.data(), static_cast<int>(honest.size()));
  bus.Drain();
  EXPECT_EQ(handled, 1);  // the bus lives on
}

}  // namespace
}  // namespace viscera::bus
