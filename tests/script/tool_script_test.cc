#include "script/tool_script.h"

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
  EXPECT_NEAR(mid.orientation.angularDistance(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()))), 0.0, 1e-12);
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
  EXPECT_NE(error("t,tool,x,y,z,qw,qx,qy,qz,jaw\n0,a,0,0,nan,1,0,0,0,1\n").find("s.csv:2: z"), std::string::npos);
  EXPECT_NE(error("t,tool,x,y,z,qw,qx,qy,qz,jaw\n0,a,0,0,0,1,0,0,0,2\n").find("jaw"), std::string::npos);
  EXPECT_NE(error("t,tool,x,y,z,qw,qx,qy,qz,jaw\n1,a,0,0,0,1,0,0,0,1\n0,a,0,0,0,1,0,0,0,1\n").find("back in time"), std::string::npos);
  EXPECT_NE(error("t,tool,x,y,z,qw,qx,qy,qz,jaw\n0,a,0,0,0,0,0,0,0,1\n").find("quaternion"), std::string::npos);
  EXPECT_NE(error("").find("empty"), std::string::npos);
  EXPECT_NE(error("t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n0,a,0,0,0,1,0,0,0,1,centre\n").find("s.csv:2: aim"), std::string::npos);
  EXPECT_NE(error("t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n0,a,0,0,0,1,0,0,0,1\n").find("expected 11 columns"), std::string::npos);
}

TEST(ToolScript, RowsAimedAtTheTubeFollowItsSurface) {
  const ToolScript s = ToolScript::Parse(
      "t,tool,x,y,z,qw,qx,qy,qz,jaw,aim\n"
      "0,left,0,0,0.3,1,0,0,0,1,point\n"
      "1,left,0.02,0,0.1,1,0,0,0,0,tube\n");
  EXPECT_TRUE(s.aims_at_tube());
  // A tube of radius 1 cm along x at height 5 cm, 2 cm to the side of the aimed row's point.
  Tube tube{{Vec3(-0.1, 0.02, 0.05), Vec3(0.0, 0.02, 0.05), Vec3(0.1, 0.02, 0.05)}, 0.01};
  const Vec3 aimed = s.At("left", 1.0, tube).tip;
  const Vec3 axis(0.02, 0.02, 0.05);  // the nearest point of the centre line
  EXPECT_NEAR((aimed - axis).norm(), 0.01, 1e-12);                          // on the surface
  EXPECT_NEAR((aimed - axis).normalized().dot((Vec3(0.02, 0, 0.1) - axis).normalized()), 1.0, 1e-12);  // facing the point
  // Half way there from the unaimed first row; the tube moved: the target follows it.
  EXPECT_TRUE(s.At("left", 0.5, tube).tip.isApprox(0.5 * (Vec3(0, 0, 0.3) + aimed)));
  for (Vec3& c : tube.centre_line) c.z() -= 0.03;
  EXPECT_NEAR(s.At("left", 1.0, tube).tip.z(), aimed.z() - 0.03, 0.005);
  // Without the tube (no skeleton yet), the written point.
  EXPECT_EQ(s.At("left", 1.0).tip, Vec3(0.02, 0, 0.1));
  // A point inside the tube is its own target.
  EXPECT_EQ(NearestOnTube(tube, Vec3(0.0, 0.02, 0.022)), Vec3(0.0, 0.02, 0.022));
}

}  // namespace
}  // namespace viscera::script
