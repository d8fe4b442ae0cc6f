#pragma once
// What the session e2e tests share: a status polled until it holds, the one-tool push scene and
// a tool pose with a token.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <viscera_proto/tool_pose_t.hpp>

#include "bus/header.h"
#include "common/types.h"
#include "tests/common/eventually.h"
#include "tests/e2e/e2e_harness.h"

namespace viscera::e2e {

// Polls the status of `id` until `done` holds (or 30 s pass: the test then fails, showing the
// last status). No fixed sleep: as fast as the server gets there, however loaded the machine.
inline nlohmann::json StatusWhen(const std::string& dir, int64_t id,
                                 const std::function<bool(const nlohmann::json&)>& done,
                                 const std::string& extra = "") {
  nlohmann::json s;
  EXPECT_TRUE(testing::Eventually(
      [&] {
        s = TryStatus(dir, id, extra);
        return !s.is_null() && done(s);
      },
      30.0, [] { Sleep(0.05); }))
      << "last status: " << s.dump();
  return s;
}

inline std::string PushScene() {
  return std::string(VISCERA_SOURCE_DIR) + "/tests/e2e/scenes/push.toml";
}

inline viscera_proto::tool_pose_t Pose(int64_t id, const std::vector<uint8_t>& token, int64_t seq,
                                       const Vec3& p) {
  viscera_proto::tool_pose_t pose{};
  pose.header = bus::MakeHeader(id, seq);
  pose.header.token = token;
  pose.header.token_len = static_cast<int32_t>(token.size());
  pose.tool = 0;
  for (int a = 0; a < 3; ++a) pose.position[a] = p(a);
  pose.orientation[0] = 1.0;
  pose.jaw = 1.0;
  return pose;
}

}  // namespace viscera::e2e
