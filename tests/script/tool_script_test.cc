#include "script/tool_script.h"
#include "script/script_player.h"

#include <gtest/gtest.h>

#include "common/check.h"

namespace viscera::script {
namespace {

const char* kScript =
    "t,tool,x,y,z,qw,qx,qy,qz,jaw\n"
    "# a comment\n"
    "0.0,left,0,0,0.3,1,0,0,0,1\n"
    "1.0,left,0.1,0,0.2,0,0,0,1,0\n"
    "0.5,right,0,0.1,0.3,1,0,0,0,1\n";

TEST(ToolScript, InterpolatesBetweenRowsAndHoldsOutside) {
  const ToolScript s = ToolScript::Parse(kScript);
  EXPECT_TRUE(s.Has("left"));
  EXPECT_TRUE(s.Has("right"));
  EXPECT_FALSE(s.Has("camera"));
  EXPECT_EQ(s.duration(), 1.0);
  const ToolKeyframe mid = s.At("left", 0.5);
  EXPECT_TRUE(mid.tip.isApprox(Vec3(0.05, 0, 0.25)));
  EXPECT_DOUBLE_EQ(mid.jaw, 0.5);
  // Half way from identity to a half turn about z: a quarter turn.
  EXPECT_NEAR(mid.orientation.angularDistance(
                  Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()))),
              0.0, 1e-12);
  EXPECT_EQ(s.At("left", -1.0).tip, Vec3(0, 0, 0.3));
  EXPECT_EQ(s.At("left", 5.0).tip, Vec3(0.1, 0, 0.2));
  EXPECT_EQ(s.At("right", 0.0).tip, Vec3(0, 0.1, 0.3));
}

TEST(ToolScript, MalformedScriptsNameLineAndColumn) {
  auto error = [](const std::string& text) {
    try {
      ToolScript::Parse(text, "s.csv");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("t,tool,x,y,z\n").find("header"), std::string::npos);
  EXPECT_NE(error("t,tool,x,y,z,qw,qx,qy,qz,jaw\n0,a,0,0,nan,1,0,0,0,1\n").find("s.csv:2: z"),
            std::string::npos);
  EXPECT_NE(error("t,tool,x,y,z,qw,qx,qy,qz,jaw\n0,a,0,0,0,1,0,0,0,2\n").find("jaw"),
            std::string::npos);
  EXPECT_NE(error("t,tool,x,y,z,qw,qx,qy,qz,jaw\n1,a,0,0,0,1,0,0,0,1\n0,a,0,0,0,1,0,0,0,1\n")
                .find("back in time"),
            std::string::npos);
  EXPECT_NE(error("t,tool,x,y,z,qw,qx,qy,qz,jaw\n0,a,0,0,0,0,0,0,0,1\n").find("quaternion"),
            std::string::npos);
  EXPECT_NE(error("").find("empty"), std::string::npos);
  EXPECT_NE(
      error("t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n0,a,0,0,0,1,0,0,0,1,centre\n").find("s.csv:2: aim"),
      std::string::npos);
  EXPECT_NE(
      error("t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n0,a,0,0,0,1,0,0,0,1\n").find("expected 11 columns"),
      std::string::npos);
}

// tube@S aims at one part of the bowel: the point at arc-length fraction S of the centre line
// (not of its vertices), on the surface facing the row's position, wherever the tube lies.
TEST(ToolScript, ARowAimedAlongTheTubeTakesThatPartOfTheBowel) {
  const ToolScript s = ToolScript::Parse(
      "t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n"
      "0,left,0,0,0.3,1,0,0,0,1,point\n"
      "1,left,0,0,0.3,1,0,0,0,1,tube@0.6\n");
  EXPECT_TRUE(s.aims_at_tube());
  EXPECT_DOUBLE_EQ(s.frames("left")[1].along, 0.6);
  // 10 cm along x, then 10 and 30 cm along y (uneven vertices): 0.6 of 50 cm is 30 cm in,
  // 10 cm into the last piece.
  Tube tube{{Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.1, 0.1, 0), Vec3(0.1, 0.4, 0)}, 0.01};
  ScriptPlayer player(s);
  EXPECT_TRUE(player.At("left", 1.0, tube)
                  .tip.isApprox(Vec3(0.1, 0.2, 0.0) +
                                0.01 * (Vec3(0, 0, 0.3) - Vec3(0.1, 0.2, 0)).normalized()));
  // the same part of the bowel when the tube lies elsewhere
  for (Vec3& c : tube.centre_line) c = Vec3(c.y(), -c.x(), 0.05);
  EXPECT_NEAR((AlongTube(tube, 0.6, Vec3(0, 0, 0.3)) - Vec3(0.2, -0.1, 0.05)).norm(), 0.01, 1e-12);
  EXPECT_TRUE(AlongTube(tube, 1.5, Vec3(0.4, -0.1, 1))
                  .isApprox(Vec3(0.4, -0.1, 0.06)));  // clamped to the end
  EXPECT_EQ(AlongTube(Tube{}, 0.5, Vec3(1, 2, 3)), Vec3(1, 2, 3));
  auto error = [](const std::string& aim) {
    try {
      ToolScript::Parse("t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n0,a,0,0,0,1,0,0,0,1," + aim + "\n",
                        "s.csv");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  for (const char* bad : {"tube@", "tube@1.5", "tube@-0.1", "tube@x", "tube@0.5x", "tubes"}) {
    EXPECT_NE(error(bad).find("s.csv:2: aim"), std::string::npos) << bad;
  }
}

TEST(ScriptPlayer, AnAimedRowIsResolvedOnTheTubeWhenItsSegmentBeginsAndThenHeld) {
  const ToolScript s = ToolScript::Parse(
      "t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n"
      "0,left,0,0,0.3,1,0,0,0,1,point\n"
      "1,left,0.02,0,0.1,1,0,0,0,1,tube\n"
      "2,left,0.02,0,0.1,1,0,0,0,0,tube\n");
  EXPECT_TRUE(s.aims_at_tube());
  ScriptPlayer player(s);
  // A tube of radius 1 cm along x at height 5 cm, 2 cm to the side of the aimed rows' point.
  Tube tube{{Vec3(-0.1, 0.02, 0.05), Vec3(0.0, 0.02, 0.05), Vec3(0.1, 0.02, 0.05)}, 0.01};
  // No tube seen yet: the written points stand in, and nothing is resolved.
  EXPECT_EQ(player.At("left", 0.0, Tube{}).tip, Vec3(0, 0, 0.3));
  // The second row's segment began at 0: aimed at the tube as it is at the first call that sees it.
  const Vec3 aimed = player.At("left", 0.5, tube).tip * 2.0 - Vec3(0, 0, 0.3);
  const Vec3 axis(0.02, 0.02, 0.05);                // the nearest point of the centre line
  EXPECT_NEAR((aimed - axis).norm(), 0.01, 1e-12);  // on the surface
  EXPECT_NEAR((aimed - axis).normalized().dot((Vec3(0.02, 0, 0.1) - axis).normalized()), 1.0,
              1e-12);  // facing the point
  // The tube moves 3 cm down before t = 1: the second row holds, the third (its segment begins
  // at 1) is aimed at the tube where it then is, and holds after it moves again.
  for (Vec3& c : tube.centre_line) c.z() -= 0.03;
  EXPECT_TRUE(player.At("left", 0.9, tube).tip.isApprox(0.1 * Vec3(0, 0, 0.3) + 0.9 * aimed));
  EXPECT_TRUE(player.At("left", 1.0, tube).tip.isApprox(aimed));
  const Vec3 third = player.At("left", 2.0, tube).tip;
  EXPECT_NEAR(third.z(), aimed.z() - 0.03, 0.005);
  for (Vec3& c : tube.centre_line) c.z() += 0.05;
  EXPECT_EQ(player.At("left", 2.5, tube).tip, third);
  // The script itself keeps the written points.
  EXPECT_EQ(s.At("left", 1.0).tip, Vec3(0.02, 0, 0.1));
  // A point inside the tube is its own target.
  EXPECT_EQ(NearestOnTube(tube, Vec3(0.0, 0.02, 0.072)), Vec3(0.0, 0.02, 0.072));
}

// Hand over hand lifts what the jaws grasped, wherever the pile put it: an offset row moves from
// where the tool's last aimed row landed.
TEST(ScriptPlayer, AnOffsetRowLiftsFromWhereTheLastAimedRowLanded) {
  const ToolScript s = ToolScript::Parse(
      "t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n"
      "0,left,0,0,0.3,1,0,0,0,1,point\n"
      "1,left,0,0,0.3,1,0,0,0,0,tube@0.5\n"
      "2,left,0,0,0.04,1,0,0,0,0,offset\n");
  ScriptPlayer player(s);
  Tube tube{{Vec3(-0.1, 0.0, 0.05), Vec3(0.1, 0.0, 0.05)}, 0.01};
  const Vec3 grasped = player.At("left", 1.0, tube).tip;
  EXPECT_TRUE(grasped.isApprox(Vec3(0.0, 0.0, 0.06)));  // the top of the tube's middle
  EXPECT_TRUE(player.At("left", 2.0, tube).tip.isApprox(grasped + Vec3(0, 0, 0.04)));
  EXPECT_THROW(ToolScript::Parse("t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n0,a,0,0,0,1,0,0,0,1,offset\n"),
               InputError);
}

}  // namespace
}  // namespace viscera::script
