#pragma once
/// LCM channel names of the viscera protocol (docs/protocol.md lists them with their types).

namespace viscera::bus {

/// viscera_proto::heartbeat_t, once a second from every viscerad.
inline constexpr char kHeartbeatChannel[] = "VISCERA_HEARTBEAT";

}  // namespace viscera::bus
