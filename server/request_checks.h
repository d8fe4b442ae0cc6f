#pragma once
/// The checks of a request or pose that need only the message and the server's configured
/// limits: what the server's state (sessions, load, replays, tokens) decides is admission's.
#include <string>

#include <viscera_proto/session_request_t.hpp>
#include <viscera_proto/tool_pose_t.hpp>

#include "server/server_config.h"
#include "session/session.h"

namespace viscera::server {

/// Largest |coordinate| of a pose or camera (m): no operating room is larger.
inline constexpr double kMaxPosition = 10.0;

/// Why a pose cannot drive tool `tool` of a session with `num_tools` tools ("" if it can):
/// out-of-range tool index, non-finite or out-of-range position (|x| <= 10 m), orientation
/// (norm within 0.5..2) or jaw (0..1).
std::string PoseProblem(const viscera_proto::tool_pose_t& pose, int num_tools);

/// Smallest frame side a stream may have (pixels).
inline constexpr int kMinFrameSide = 16;

/// Why frames of these settings cannot be served within `limits` (max_frame_width,
/// max_frame_height, max_frame_rate_hz), or "" when they can: a create's (0 or "" = the
/// server default) and viscerad's own defaults alike. Rates < 0 mean no frames.
std::string FrameSettingsProblem(int width, int height, double rate_hz, int jpeg_quality,
                                 const std::string& skin_name, const ServerConfig& limits);

/// Why a create asks for what no session of this server may have ("" if it may): its skeleton
/// rate and frame settings (FrameSettingsProblem).
std::string CreateSettingsProblem(const viscera_proto::session_request_t& request,
                                  const ServerConfig& limits);

/// The camera a kCamera request sets.
session::CameraPose CameraPoseOf(const viscera_proto::session_request_t& request);

/// Whether `pose` can be drawn: finite, within kMaxPosition, eye and target apart, up neither
/// zero nor along the view, fov within (1, 179) degrees.
bool CameraPoseUsable(const session::CameraPose& pose);

}  // namespace viscera::server
