#include <gtest/gtest.h>

#include <cmath>

#include "common/check.h"
#include "haptic/replay_device.h"
#include "haptic/sim_device.h"

namespace viscera::haptic {
namespace {

script::ToolScript Hold(double z) {
  return script::ToolScript::Parse("t,tool,x,y,z,qw,qx,qy,qz,jaw\n0,hand,0,0," + std::to_string(z) +
                                   ",1,0,0,0,1\n1,hand,0,0," + std::to_string(z) +
                                   ",1,0,0,0,0.5\n");
}

TEST(SimDevice, AConstantForceDisplacesTheHandByHookesLaw) {
  SimHandOptions o;
  SimDevice hand(Hold(0.1), "hand", o);
  EXPECT_EQ(hand.Read(0.0).position, Vec3(0, 0, 0.1));
  hand.Write(Vec3(0, 0, 1.5));  // pushes the hand up
  DeviceSample s;
  for (int ms = 1; ms <= 3000; ++ms) s = hand.Read(ms * 1e-3);
  // at rest: k (target - x) + F = 0
  EXPECT_NEAR(s.position.z(), 0.1 + 1.5 / o.stiffness_n_m, 1e-6);
  EXPECT_NEAR(hand.velocity().norm(), 0.0, 1e-6);
  EXPECT_NEAR(s.jaw, 0.5, 1e-12);  // the script's jaw, held after its end
}

TEST(SimDevice, FollowsItsScriptWithTheLagOfAMassSpringDamper) {
  SimDevice hand(script::ToolScript::Parse("t,tool,x,y,z,qw,qx,qy,qz,jaw\n0,hand,0,0,0,1,0,0,0,1\n"
                                           "1,hand,0.1,0,0,1,0,0,0,1\n"),
                 "hand");
  DeviceSample s;
  for (int ms = 1; ms <= 500; ++ms) s = hand.Read(ms * 1e-3);
  // a ramp of 0.1 m/s, followed with a lag of (b_h + b_d) / k seconds once settled
  const double lag = (8.0 + 0.5) / 300.0 * 0.1;
  EXPECT_NEAR(s.position.x(), 0.05 - lag, 2e-4);
  EXPECT_THROW(SimDevice(Hold(0.0), "other"), InputError);
}

TEST(ReplayDevice, InterpolatesALogAndHoldsItsLastSample) {
  ReplayDevice d = ReplayDevice::Parse(
      "{\"t\":10.0,\"position\":[0,0,0],\"force\":[0,0,0]}\n"
      "{\"t\":10.5,\"position\":[0.1,0,-0.2]}\n\n"
      "{\"t\":11.0,\"position\":[0.1,0,-0.2]}\n",
      "log");
  EXPECT_DOUBLE_EQ(d.duration(), 1.0);
  EXPECT_NEAR((d.Read(0.25).position - Vec3(0.05, 0, -0.1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((d.Read(0.75).position - Vec3(0.1, 0, -0.2)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((d.Read(5.0).position - Vec3(0.1, 0, -0.2)).norm(), 0.0, 1e-12);
}

TEST(ReplayDevice, NamesTheLineOfAnythingMalformed) {
  auto error = [](const std::string& text) {
    try {
      ReplayDevice::Parse(text, "log.jsonl");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("{\"t\":0,\"position\":[0,0,0]}\nnot json\n").find("log.jsonl:2"),
            std::string::npos);
  EXPECT_NE(error("{\"t\":0}\n").find("log.jsonl:1"), std::string::npos);
  EXPECT_NE(error("{\"t\":1,\"position\":[0,0,0]}\n{\"t\":0.5,\"position\":[0,0,0]}\n")
                .find("back in time"),
            std::string::npos);
  EXPECT_NE(error("").find("no samples"), std::string::npos);
  EXPECT_NE(error("{\"t\":0,\"position\":[0,\"x\",0]}\n").find("position[1]"), std::string::npos);
}

}  // namespace
}  // namespace viscera::haptic
