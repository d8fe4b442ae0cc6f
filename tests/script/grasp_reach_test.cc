// A grasp row looks before the jaws close: jaws beside another strand back off and reach again,
// while the script's clock stands for every tool; jaws at the aimed part go on as written.
#include <gtest/gtest.h>

#include <string>

#include "common/check.h"
#include "script/script_player.h"
#include "script/tool_script.h"

namespace viscera::script {
namespace {

// A loop of radius 1 cm folded back on itself: a strand along x at y = 0, 3 cm of turn, and a
// strand back along x at y = 3 cm, 43 cm in all, 5 cm up.
Tube Hairpin() {
  return Tube{
      {Vec3(-0.1, 0.0, 0.05), Vec3(0.1, 0.0, 0.05), Vec3(0.1, 0.03, 0.05), Vec3(-0.1, 0.03, 0.05)},
      0.01};
}

constexpr double kLength = 0.43;
// the first strand at x = -0.05, as a row writes it
const double kAimed = std::stod(std::to_string(0.05 / kLength));

// The left grasper waits above the loop, reaches for the first strand at x = -0.05, arrives
// (grasp row) at 2 s, closes and lifts; the right one moves on its own from 0 to 3 s.
ToolScript Reach() {
  const std::string s = std::to_string(kAimed);
  return ToolScript::Parse(
      "t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n"
      "0,left,-0.05,-0.05,0.2,1,0,0,0,1,point\n"
      "1,left,-0.05,-0.05,0.2,1,0,0,0,1,tube@" +
      s +
      "\n"
      "2,left,-0.05,-0.05,0.2,1,0,0,0,1,grasp@" +
      s +
      "\n"
      "2.5,left,0,0,0.04,1,0,0,0,0.2,offset\n"
      "0,right,0.1,0.1,0.3,1,0,0,0,1,point\n"
      "3,right,0.4,0.1,0.3,1,0,0,0,1,point\n");
}

TEST(GraspRow, JawsAtTheAimedPartGoOnAsWritten) {
  const ToolScript script = Reach();
  EXPECT_TRUE(script.frames("left")[2].grasp);
  EXPECT_TRUE(script.frames("left")[2].at_tube);
  ScriptPlayer player(script);
  const Tube tube = Hairpin();
  for (int k = 0; k < 200; ++k) player.At("left", 0.01 * k, tube);
  // the first strand's surface at x = -0.05, facing the approach
  const Vec3 target = AlongTube(tube, kAimed, Vec3(-0.05, -0.05, 0.2));
  EXPECT_NEAR(target.x(), -0.05, 1e-6);
  // the tip where the target is: no reach, the script as written
  EXPECT_TRUE(player.At("left", 2.0, tube, &target).tip.isApprox(target));
  const ToolKeyframe k = player.At("left", 2.25, tube, &target);
  EXPECT_EQ(player.reaches(), 0);
  EXPECT_EQ(player.delay(), 0.0);
  EXPECT_NEAR(k.jaw, 0.6, 1e-12);
  EXPECT_NEAR(player.At("right", 1.5, tube).tip.x(), 0.25, 1e-12);
}

TEST(GraspRow, JawsBesideAnotherStrandBackOffAndReachAgainWhileTheClockStands) {
  ScriptPlayer player(Reach());
  const Tube tube = Hairpin();
  for (int k = 0; k < 200; ++k) player.At("left", 0.01 * k, tube);
  const Vec3 aimed = AlongTube(tube, kAimed, Vec3(-0.05, -0.05, 0.2));
  // The jaws came down on the other strand (3 cm over, 33 cm away along the loop).
  const Vec3 beside(-0.05, 0.02, 0.05);
  EXPECT_NEAR(AlongTubeFrom(tube, kAimed, beside), 0.33, 1e-6);
  ToolKeyframe k = player.At("left", 2.0, tube, &beside);
  EXPECT_EQ(player.reaches(), 1);
  EXPECT_TRUE(k.tip.isApprox(aimed));  // from where it is
  EXPECT_EQ(k.jaw, 1.0);               // the jaws stay open
  // It backs off to its last point in the second the script gave it to leave it ...
  EXPECT_TRUE(player.At("left", 3.0, tube, &beside).tip.isApprox(Vec3(-0.05, -0.05, 0.2)));
  // ... while the other hand's clock stands at 2 s (two thirds of its way).
  for (double t : {2.0, 2.7, 4.4}) EXPECT_NEAR(player.At("right", t, tube).tip.x(), 0.3, 1e-12);
  EXPECT_FALSE(player.Done(10.0));
  // and reaches again: the tube@ row at 4 s, the grasp row at 5 s, aimed anew (the tube moved).
  Tube moved = tube;
  for (Vec3& c : moved.centre_line) c.x() += 0.01;
  const Vec3 again = player.At("left", 4.99, moved, &beside).tip;
  EXPECT_NEAR(again.x(), -0.04, 2e-3);
  // Now at the aimed part: the script goes on from 2 s, 3 s late.
  const Vec3 there(-0.04, -0.01, 0.05);
  player.At("left", 5.0, moved, &there);
  EXPECT_EQ(player.reaches(), 1);
  EXPECT_NEAR(player.delay(), 3.0, 1e-12);
  EXPECT_NEAR(player.At("left", 5.25, moved, &there).jaw, 0.6, 1e-12);
  EXPECT_NEAR(player.At("right", 5.5, moved).tip.x(), 0.35, 1e-12);
  EXPECT_FALSE(player.Done(5.9));
  EXPECT_TRUE(player.Done(6.0));
}

TEST(GraspRow, AfterItsLastReachTheScriptGoesOn) {
  ScriptPlayer player(Reach());
  const Tube tube = Hairpin();
  const Vec3 beside(-0.05, 0.02, 0.05);
  int k = 0;
  for (; k < 2000 && player.reaches() < ScriptPlayer::kMaxReaches; ++k)
    player.At("left", 0.01 * k, tube, &beside);
  EXPECT_NEAR(0.01 * k, 8.0, 0.025);  // reaches at 2, 5 and 8 s (each takes 3 s)
  for (; k < 1150; ++k) player.At("left", 0.01 * k, tube, &beside);
  EXPECT_EQ(player.reaches(), ScriptPlayer::kMaxReaches);
  EXPECT_NEAR(player.delay(), 9.0, 0.025);
  EXPECT_LT(player.At("left", 11.5, tube, &beside).jaw, 1.0);  // closing, on whatever is there
}

TEST(GraspRow, WithoutTheTipOrTheTubeItIsNotChecked) {
  ScriptPlayer player(Reach());
  for (int k = 0; k <= 300; ++k) player.At("left", 0.01 * k, Hairpin());
  ScriptPlayer blind(Reach());
  const Vec3 beside(-0.05, 0.02, 0.05);
  for (int k = 0; k <= 300; ++k) blind.At("left", 0.01 * k, Tube{}, &beside);
  EXPECT_EQ(player.reaches() + blind.reaches(), 0);
}

// A script of one grasp row has nowhere to back off to: it looks again where it is, three
// times, and goes on.
TEST(GraspRow, AGraspRowAloneReachesAgainWhereItIs) {
  ScriptPlayer player(
      ToolScript::Parse("t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n0,left,0,0,0.2,1,0,0,0,1,grasp@0.1\n"));
  const Vec3 beside(-0.05, 0.02, 0.05);
  for (int k = 0; k < 10; ++k) player.At("left", 0.01 * k, Hairpin(), &beside);
  EXPECT_EQ(player.reaches(), ScriptPlayer::kMaxReaches);
  EXPECT_TRUE(player.Done(0.1));
}

TEST(GraspRow, MalformedGraspRowsNameLineAndColumn) {
  for (const char* bad : {"grasp@", "grasp@1.5", "grasp@x", "grasp"}) {
    try {
      ToolScript::Parse(std::string("t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n0,a,0,0,0,1,0,0,0,1,") + bad,
                        "s.csv");
      ADD_FAILURE() << bad << " parsed";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("s.csv:2: aim"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace viscera::script
