#pragma once
/// LCM channel names of the viscera protocol (docs/protocol.md lists them with their types).
#include <cstdint>
#include <string>

namespace viscera::bus {

/// viscera_proto::heartbeat_t, once a second from every viscerad.
inline constexpr char kHeartbeatChannel[] = "VISCERA_HEARTBEAT";
/// viscera_proto::session_request_t, clients -> servers.
inline constexpr char kRequestChannel[] = "VISCERA_SESSION_REQUEST";
/// viscera_proto::session_reply_t, servers -> clients.
inline constexpr char kReplyChannel[] = "VISCERA_SESSION_REPLY";

/// Prefixes of the per-session channels; the session id follows in decimal.
inline constexpr char kPosePrefix[] = "VISCERA_POSE_";          ///< tool_pose_t, client -> server
inline constexpr char kForcePrefix[] = "VISCERA_FORCE_";        ///< force_feedback_t
inline constexpr char kSkeletonPrefix[] = "VISCERA_SKELETON_";  ///< skeleton_state_t
inline constexpr char kStatusPrefix[] = "VISCERA_STATUS_";      ///< session_status_t
inline constexpr char kFramePrefix[] = "VISCERA_FRAME_";        ///< jpeg_frame_t
inline constexpr char kStepPrefix[] = "VISCERA_STEP_";          ///< step_record_t, records only
inline constexpr char kScenePrefix[] = "VISCERA_SCENE_";        ///< session_request_t, records only

/// `prefix` followed by the session id, e.g. SessionChannel(kPosePrefix, 42) = "VISCERA_POSE_42".
inline std::string SessionChannel(const char* prefix, int64_t session_id) {
  return std::string(prefix) + std::to_string(session_id);
}

}  // namespace viscera::bus
