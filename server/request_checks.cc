#include "server/request_checks.h"

#include <cmath>

#include "common/check.h"
#include "server/frame_schedule.h"
#include "skin/skin.h"

namespace viscera::server {

std::string PoseProblem(const viscera_proto::tool_pose_t& pose, int num_tools) {
  if (pose.tool < 0 || pose.tool >= num_tools) {
    return Cat("tool ", pose.tool, " does not exist (the scene has ", num_tools, ")");
  }
  for (const double x : pose.position) {
    if (!std::isfinite(x) || std::abs(x) > kMaxPosition) {
      return Cat("position (", pose.position[0], ", ", pose.position[1], ", ", pose.position[2],
                 ") m: not finite or beyond ", kMaxPosition, " m");
    }
  }
  double norm2 = 0.0;
  for (const double c : pose.orientation) norm2 += c * c;
  if (!std::isfinite(norm2) || norm2 < 0.25 || norm2 > 4.0) {
    return Cat("orientation quaternion of norm ", std::sqrt(norm2), ": not a rotation");
  }
  if (!std::isfinite(pose.jaw) || pose.jaw < 0.0 || pose.jaw > 1.0) {
    return Cat("jaw ", pose.jaw, ": must be within [0, 1]");
  }
  return "";
}

std::string FrameSettingsProblem(int width, int height, double rate_hz, int jpeg_quality,
                                 const std::string& skin_name, const ServerConfig& limits) {
  // every stream holds a frame buffer and a render thread: the server caps their size
  const auto side_ok = [](int side, int max) {
    return side == 0 || (side >= kMinFrameSide && side <= max);
  };
  if (!side_ok(width, limits.max_frame_width) || !side_ok(height, limits.max_frame_height)) {
    return Cat("frame size ", width, "x", height,
               ": each side must be 0 (server default) or within ", kMinFrameSide, "..",
               limits.max_frame_width, "x", limits.max_frame_height, " pixels");
  }
  if (!std::isfinite(rate_hz) || rate_hz > limits.max_frame_rate_hz ||
      (rate_hz > 0.0 && rate_hz < kMinFrameRateHz)) {
    return Cat("frame rate ", rate_hz, " Hz: must be within ", kMinFrameRateHz, "..",
               limits.max_frame_rate_hz, " Hz (0 = server default, < 0 = no frames)");
  }
  if (jpeg_quality < 0 || jpeg_quality > 100) {
    return Cat("JPEG quality ", jpeg_quality, ": must be within 1..100 (0 = server default)");
  }
  if (!skin_name.empty() && !skin::IsSkinName(skin_name)) {
    return Cat("unknown skin '", skin_name, "' (expected ", skin::kSkinNameList, ")");
  }
  return "";
}

std::string CreateSettingsProblem(const viscera_proto::session_request_t& request,
                                  const ServerConfig& limits) {
  if (!std::isfinite(request.skeleton_rate_hz) || request.skeleton_rate_hz > 1000.0) {
    return "skeleton rate must be at most 1000 Hz";
  }
  return FrameSettingsProblem(request.frame_width, request.frame_height, request.frame_rate_hz,
                              request.jpeg_quality, request.skin, limits);
}

session::CameraPose CameraPoseOf(const viscera_proto::session_request_t& request) {
  session::CameraPose pose;
  pose.eye = Vec3(request.camera_eye[0], request.camera_eye[1], request.camera_eye[2]);
  pose.target = Vec3(request.camera_target[0], request.camera_target[1], request.camera_target[2]);
  pose.up = Vec3(request.camera_up[0], request.camera_up[1], request.camera_up[2]);
  pose.fov_deg = request.camera_fov_deg;
  pose.set_by_client = true;
  return pose;
}

bool CameraPoseUsable(const session::CameraPose& pose) {
  const Vec3 view = pose.target - pose.eye;
  return pose.eye.allFinite() && pose.target.allFinite() && pose.up.allFinite() &&
         pose.eye.cwiseAbs().maxCoeff() <= kMaxPosition &&
         pose.target.cwiseAbs().maxCoeff() <= kMaxPosition && view.norm() > 1e-6 &&
         pose.up.norm() > 1e-9 && view.normalized().cross(pose.up.normalized()).norm() > 1e-6 &&
         std::isfinite(pose.fov_deg) && pose.fov_deg > 1.0 && pose.fov_deg < 179.0;
}

}  // namespace viscera::server
