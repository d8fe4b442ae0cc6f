#pragma once
/// Filling a tool_pose_t: one place for the field order (position, quaternion w x y z, jaw) and
/// the token, for every client that streams poses (viscera drive, the haptic device loop).
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <viscera_proto/tool_pose_t.hpp>

#include "bus/header.h"
#include "common/types.h"

namespace viscera::bus {

/// Fills `pose` (reused by the caller, so its token vector keeps its capacity) for `tool` of
/// session `session_id`, sequence `seq`, stamped now. Positions in m, world frame.
inline void FillToolPose(int64_t session_id, int64_t seq, const std::vector<uint8_t>& token,
                         int tool, const Vec3& tip, const Eigen::Quaterniond& orientation,
                         double jaw, viscera_proto::tool_pose_t* pose) {
  pose->header = MakeHeader(session_id, seq);
  pose->header.token = token;
  pose->header.token_len = static_cast<int32_t>(token.size());
  pose->tool = tool;
  for (int a = 0; a < 3; ++a) pose->position[a] = tip(a);
  pose->orientation[0] = orientation.w();
  pose->orientation[1] = orientation.x();
  pose->orientation[2] = orientation.y();
  pose->orientation[3] = orientation.z();
  pose->jaw = jaw;
}

}  // namespace viscera::bus
