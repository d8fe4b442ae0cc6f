#include "server/frame_schedule.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace viscera::server {
namespace {

constexpr int64_t kPeriod = 40;  // any unit: the arithmetic is the same in ns

TEST(FrameSchedule, AFrameOnTimeGoesToTheNextTick) {
  int64_t next = 1000;
  EXPECT_EQ(AdvanceFrameSchedule(&next, 1010, kPeriod), 0);
  EXPECT_EQ(next, 1040);
}

TEST(FrameSchedule, AFrameLessThanAPeriodLateIsServedAtOnce) {
  int64_t next = 1000;
  // the frame of tick 1000 ended at 1070: tick 1040 is late but not dropped
  EXPECT_EQ(AdvanceFrameSchedule(&next, 1070, kPeriod), 0);
  EXPECT_EQ(next, 1040);
}

TEST(FrameSchedule, TicksPassedEntirelyAreDroppedAndTheGridIsKept) {
  int64_t next = 1000;
  // ended at 1130: ticks 1040 and 1080 passed entirely, 1120 is served now
  EXPECT_EQ(AdvanceFrameSchedule(&next, 1130, kPeriod), 2);
  EXPECT_EQ(next, 1120);
  EXPECT_EQ((next - 1000) % kPeriod, 0);
  // exactly a period past the next tick: that tick is dropped, the one at `now` served
  next = 1000;
  EXPECT_EQ(AdvanceFrameSchedule(&next, 1080, kPeriod), 1);
  EXPECT_EQ(next, 1080);
}

TEST(FrameSchedule, FramesPlusDroppedCountEveryTickOfALongRun) {
  // a renderer taking 1.5 periods per frame: every tick is either served or dropped, and the
  // renderer never idles (a late tick is served at once), so it serves 1 / 1.5 of them
  int64_t next = 0, now = 0, served = 0, dropped = 0;
  const int64_t end = 1000 * kPeriod;
  while (next < end) {
    now = std::max(now, next) + kPeriod * 3 / 2;
    ++served;
    dropped += AdvanceFrameSchedule(&next, now, kPeriod);
  }
  EXPECT_EQ(served + dropped, end / kPeriod);
  EXPECT_NEAR(static_cast<double>(served) / (end / kPeriod), 2.0 / 3.0, 0.01);
}

}  // namespace
}  // namespace viscera::server
