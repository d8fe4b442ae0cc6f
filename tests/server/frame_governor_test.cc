// FrameGovernor: down under sustained overload (rate first, then size), back up once calm,
// and no oscillation in between (hysteresis).
#include "server/frame_governor.h"

#include <gtest/gtest.h>

#include <vector>

#include "session/loop_stats.h"

namespace viscera::server {
namespace {

constexpr double kPeriodMs = 40.0;  // 25 Hz configured

double Period(const FrameGovernor& g) { return kPeriodMs / g.current().rate; }

/// A governor fed as the render thread feeds it, for 10 s: 40 status periods of 100 Hz
/// mechanics (25 steps with a 10 ms period each), of which `long_steps` take 9.5 ms of wall time
/// and the others 3 ms; six cheap frames (10 ms at full size) per status period, each read with
/// the slack (session::StepSlack) of the status period before.
FrameGovernor FedWithLongSteps(int long_steps) {
  FrameGovernor g;
  session::LoopStats stats;
  double slack = 1.0;
  for (int period = 0; period < 40; ++period) {
    for (int frame = 0; frame < 6; ++frame) {
      g.Update(10.0 * g.current().scale * g.current().scale, Period(g), slack);
    }
    for (int step = 0; step < 25; ++step) {
      const bool long_step = (step + 7 * period) % 25 < long_steps;  // anywhere in the period
      stats.RecordWall(long_step ? 9'500'000 : 3'000'000);
    }
    slack = session::StepSlack(stats.Summarize(/*elapsed_ns=*/250'000'000), 100.0);
  }
  return g;
}

TEST(FrameGovernor, AStrayLongStepOrTwoLowerNothing) {
  // a machine busy with other work delays a step or two of every status period: the stream
  // stays as asked
  EXPECT_EQ(FedWithLongSteps(1).level(), 0);
  EXPECT_EQ(FedWithLongSteps(2).level(), 0);
}

TEST(FrameGovernor, ManyLongStepsLowerTheStream) {
  // 6 of every 25 steps within 0.5 ms of their deadline: the slack is short, the stream goes
  // down to its lowest level, cheap as its frames are
  const FrameGovernor g = FedWithLongSteps(6);
  EXPECT_EQ(g.level(), static_cast<int>(kFrameLevels.size()) - 1);
}

TEST(FrameGovernor, SustainedSlowFramesLowerTheRateThenTheSize) {
  FrameGovernor g;
  std::vector<FrameLevel> seen;
  for (int i = 0; i < 200; ++i) {
    // frames that cost 60 ms at full size, less at a smaller one (cost ~ pixels)
    const double cost = 60.0 * g.current().scale * g.current().scale;
    if (g.Update(cost, Period(g), 1.0)) seen.push_back(g.current());
  }
  ASSERT_GE(seen.size(), 2u);
  EXPECT_LT(seen.front().rate, 1.0);  // the rate goes first
  EXPECT_EQ(seen.front().scale, 1.0);
  // it settles where the frames fit: 60 ms at 0.4 x 25 Hz (100 ms) is not overloaded
  EXPECT_EQ(g.current().rate, 0.4);
  EXPECT_EQ(g.current().scale, 1.0);
}

TEST(FrameGovernor, ShortMechanicsSlackLowersTheSizeToo) {
  FrameGovernor g;
  for (int i = 0; i < 100; ++i) g.Update(5.0, Period(g), 0.05);  // cheap frames, starved steps
  EXPECT_LT(g.current().rate, 1.0);
  EXPECT_LT(g.current().scale, 1.0);
}

TEST(FrameGovernor, RecoversWhenTheLoadGoes) {
  FrameGovernor g;
  for (int i = 0; i < 100; ++i) g.Update(5.0, Period(g), 0.05);
  ASSERT_GT(g.level(), 0);
  for (int i = 0; i < 1000; ++i)
    g.Update(5.0 * g.current().scale * g.current().scale, Period(g), 0.9);
  EXPECT_EQ(g.level(), 0);
}

TEST(FrameGovernor, OneSlowFrameOrAShortDipMovesNothing) {
  FrameGovernor g;
  for (int i = 0; i < 100; ++i) {
    g.Update(i % 10 == 0 ? 60.0 : 10.0, kPeriodMs, 1.0);  // a spike every tenth frame
    EXPECT_EQ(g.level(), 0);
  }
}

TEST(FrameGovernor, FramesBetweenTheThresholdsHoldTheLevel) {
  // 28 ms frames: not overloaded at 40 ms (70 %), but they would not be calm at 25 Hz either
  // (0.5 x 40 = 20 ms): once lowered, the stream stays where it is instead of oscillating
  FrameGovernor g;
  for (int i = 0; i < 10; ++i) g.Update(60.0, Period(g), 1.0);
  const int lowered = g.level();
  ASSERT_GT(lowered, 0);
  for (int i = 0; i < 100; ++i) g.Update(28.0, Period(g), 1.0);  // may climb where 28 ms is calm
  const int settled = g.level();
  EXPECT_GT(settled, 0);
  EXPECT_LE(settled, lowered);
  int changes = 0;
  for (int i = 0; i < 1000; ++i) changes += g.Update(28.0, Period(g), 1.0) ? 1 : 0;
  EXPECT_EQ(changes, 0);
}

// Two streams on one core whose ticks coincide: each frame costs its thread 14 ms of CPU and
// takes 33-36 ms of wall time, the other stream's frame and both sessions' steps run in between.
FrameGovernor FedSharingACore(bool own_cpu_known) {
  FrameGovernor g;
  for (int i = 0; i < 500; ++i) {
    const double wall_ms = 33.0 + (i % 4);
    if (own_cpu_known) {
      g.Update(FrameCost{wall_ms, 14.0}, Period(g), 1.0);
    } else {
      g.Update(wall_ms, Period(g), 1.0);  // the wall time read as the frame's own cost
    }
  }
  return g;
}

TEST(FrameGovernor, AStreamSharingItsCoreKeepsItsRate) {
  // 2 x 14 ms in every 40 ms period: the core has room for both streams at 25 Hz
  EXPECT_EQ(FedSharingACore(/*own_cpu_known=*/true).level(), 0);
  // the same frames judged by their wall time alone: lowered for the other stream's frames
  EXPECT_GT(FedSharingACore(/*own_cpu_known=*/false).level(), 0);
}

TEST(FrameGovernor, FramesThatMakeTheStreamLateLowerItWhateverTheirCpu) {
  // three streams' worth of frames on one core: 13 ms each of CPU, 45 ms of wall time at a
  // 40 ms period; the stream cannot keep its rate
  FrameGovernor g;
  for (int i = 0; i < 10; ++i) g.Update(FrameCost{45.0, 13.0}, Period(g), 1.0);
  EXPECT_LT(g.current().rate, 1.0);
  EXPECT_EQ(g.current().scale, 1.0);
}

TEST(FrameGovernor, ALoweredStreamClimbsBackWhileSharingACoreWithRoom) {
  FrameGovernor g;
  for (int i = 0; i < 10; ++i) g.Update(FrameCost{45.0, 13.0}, Period(g), 1.0);
  ASSERT_GT(g.level(), 0);
  // the other stream's frames still in between (26 ms of wall time), the core no longer full
  for (int i = 0; i < 200; ++i) g.Update(FrameCost{26.0, 13.0}, Period(g), 1.0);
  EXPECT_EQ(g.level(), 0);
  // with 40 ms of wall time at 15 Hz it would have been late at 25 Hz: it stays lowered
  FrameGovernor late;
  for (int i = 0; i < 10; ++i) late.Update(FrameCost{45.0, 13.0}, Period(late), 1.0);
  const int lowered = late.level();
  for (int i = 0; i < 200; ++i) late.Update(FrameCost{40.0, 13.0}, Period(late), 1.0);
  EXPECT_EQ(late.level(), lowered);
}

}  // namespace
}  // namespace viscera::server
