// The scripted laparoscope: rows read strictly, the camera interpolated between them and held
// before the first and after the last.
#include "script/camera_script.h"

#include <gtest/gtest.h>

#include <string>

#include "common/check.h"

namespace viscera::script {
namespace {

TEST(CameraScript, InterpolatesBetweenRowsAndHoldsOutsideThem) {
  const CameraScript s = CameraScript::Parse(
      "# a scope sweeping along x\n"
      "t,ex,ey,ez,cx,cy,cz\n"
      "1.0, 0.0, -0.1, 0.3, 0.0, 0.0, 0.1\n"
      "3.0, 0.2, -0.1, 0.3, 0.1, 0.0, 0.1\n");
  EXPECT_TRUE(s.At(0.0).eye.isApprox(Vec3(0.0, -0.1, 0.3)));
  const CameraKeyframe mid = s.At(2.5);
  EXPECT_NEAR(mid.eye.x(), 0.15, 1e-12);
  EXPECT_NEAR(mid.target.x(), 0.075, 1e-12);
  EXPECT_NEAR(mid.eye.z(), 0.3, 1e-12);
  EXPECT_TRUE(s.At(10.0).target.isApprox(Vec3(0.1, 0.0, 0.1)));
}

TEST(CameraScript, RefusesMalformedScriptsSayingWhereAndWhy) {
  auto error = [](const std::string& text) {
    try {
      CameraScript::Parse(text, "cam.csv");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(error("t,ex,ey,ez,cx,cy\n").find("cam.csv:1: expected 7 columns"), std::string::npos);
  EXPECT_NE(error("t,ex,ey,ez,cx,cy,cq\n").find("column 7 is \"cq\""), std::string::npos);
  EXPECT_NE(error("t,ex,ey,ez,cx,cy,cz\n0,nan,0,0,1,1,1\n").find("cam.csv:2: ex = \"nan\""),
            std::string::npos);
  EXPECT_NE(error("t,ex,ey,ez,cx,cy,cz\n1,0,0,0,1,1,1\n0,0,0,0,1,1,1\n").find("before the row"),
            std::string::npos);
  EXPECT_NE(error("t,ex,ey,ez,cx,cy,cz\n0,1,1,1,1,1,1\n").find("on the point it looks at"),
            std::string::npos);
  EXPECT_NE(error("t,ex,ey,ez,cx,cy,cz\n").find("no camera rows"), std::string::npos);
  EXPECT_NE(error("").find("empty camera script"), std::string::npos);
}

}  // namespace
}  // namespace viscera::script
