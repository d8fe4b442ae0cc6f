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
}

}  // namespace
}  // namespace viscera::script
