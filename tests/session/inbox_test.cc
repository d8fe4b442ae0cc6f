#include "session/inbox.h"

#include <gtest/gtest.h>

namespace viscera::session {
namespace {

PoseInput Pose(int64_t seq, double x) {
  PoseInput p;
  p.seq = seq;
  p.target.tip = Vec3(x, 0.0, 0.0);
  p.client_utime = 1'000'000 + seq;
  p.received_ns = 1000 + seq;
  return p;
}

TEST(Inbox, LatestPoseWinsPerToolAndStalePosesAreDropped) {
  Inbox inbox(2);
  std::vector<PoseInput> poses;
  std::vector<Command> commands;
  inbox.Take(&poses, &commands);
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].seq, -1);  // nothing yet
  EXPECT_FALSE(poses[0].target.active);

  EXPECT_TRUE(inbox.PostPose(0, Pose(1, 0.1)));
  EXPECT_TRUE(inbox.PostPose(0, Pose(5, 0.5)));
  EXPECT_FALSE(inbox.PostPose(0, Pose(4, 0.4)));  // reordered: older than the one held
  EXPECT_FALSE(inbox.PostPose(0, Pose(5, 0.9)));  // replayed
  EXPECT_TRUE(inbox.PostPose(1, Pose(0, -0.2)));
  inbox.Take(&poses, &commands);
  EXPECT_EQ(poses[0].seq, 5);
  EXPECT_DOUBLE_EQ(poses[0].target.tip.x(), 0.5);
  EXPECT_EQ(poses[1].seq, 0);
  EXPECT_DOUBLE_EQ(poses[1].target.tip.x(), -0.2);

  // a new client starts again from seq 0, with later send times: accepted
  PoseInput restarted = Pose(0, 0.7);
  restarted.client_utime = 2'000'000;
  EXPECT_TRUE(inbox.PostPose(0, restarted));
  inbox.Take(&poses, &commands);
  EXPECT_DOUBLE_EQ(poses[0].target.tip.x(), 0.7);
}

TEST(Inbox, CommandsQueueInOrderUpToABound) {
  Inbox inbox(0);
  Command reset;
  Command pause;
  pause.kind = Command::Kind::kPause;
  EXPECT_TRUE(inbox.PostCommand(reset));
  EXPECT_TRUE(inbox.PostCommand(pause));
  std::vector<PoseInput> poses;
  std::vector<Command> commands;
  inbox.Take(&poses, &commands);
  ASSERT_EQ(commands.size(), 2u);
  EXPECT_EQ(commands[0].kind, Command::Kind::kReset);
  EXPECT_EQ(commands[1].kind, Command::Kind::kPause);
  inbox.Take(&poses, &commands);
  EXPECT_TRUE(commands.empty());  // taken once

  for (size_t i = 0; i < Inbox::kMaxCommands; ++i) EXPECT_TRUE(inbox.PostCommand(reset));
  EXPECT_FALSE(inbox.PostCommand(reset));  // a flood of commands is refused, not queued
  inbox.Take(&poses, &commands);
  EXPECT_EQ(commands.size(), Inbox::kMaxCommands);
}

}  // namespace
}  // namespace viscera::session
