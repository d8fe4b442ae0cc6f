#pragma once
// Array counts of an encoded viscera message, checked before LCM decodes it.
//
// LCM 1.3.1's generated C++ decode resizes each variable-length array to the count it read
// *before* checking that the datagram holds that many elements, so a 60-byte datagram claiming
// 2^31 frame bytes, skeleton points, statuses or tool names makes the receiver allocate (and
// zero) gigabytes, and a negative count throws from std::vector. ArrayCountsFit walks the
// message's wire layout and says whether every count fits in the bytes that follow it. The bus
// (through HeaderCountsFit, by fingerprint) and the record reader call it before every decode
// (docs/reliability.md, "Fuzzing").
#include <cstdint>

namespace viscera_proto {
class force_feedback_t;
class heartbeat_t;
class jpeg_frame_t;
class session_reply_t;
class session_request_t;
class session_status_t;
class skeleton_state_t;
class step_record_t;
class tool_pose_t;
}  // namespace viscera_proto

namespace viscera::bus {

/// True when every array count in the encoded top-level message `Msg` (fingerprint first)
/// fits in the `size` bytes of `data`. Defined for every viscera_proto top-level type.
template <typename Msg>
bool ArrayCountsFit(const uint8_t* data, int size);

/// ArrayCountsFit for the type the datagram's fingerprint names; for a fingerprint of no
/// viscera type, the header's counts only (its decode then fails on the fingerprint).
bool CountsFitForFingerprint(const uint8_t* data, int size);

template <>
bool ArrayCountsFit<viscera_proto::force_feedback_t>(const uint8_t*, int);
template <>
bool ArrayCountsFit<viscera_proto::heartbeat_t>(const uint8_t*, int);
template <>
bool ArrayCountsFit<viscera_proto::jpeg_frame_t>(const uint8_t*, int);
template <>
bool ArrayCountsFit<viscera_proto::session_reply_t>(const uint8_t*, int);
template <>
bool ArrayCountsFit<viscera_proto::session_request_t>(const uint8_t*, int);
template <>
bool ArrayCountsFit<viscera_proto::session_status_t>(const uint8_t*, int);
template <>
bool ArrayCountsFit<viscera_proto::skeleton_state_t>(const uint8_t*, int);
template <>
bool ArrayCountsFit<viscera_proto::step_record_t>(const uint8_t*, int);
template <>
bool ArrayCountsFit<viscera_proto::tool_pose_t>(const uint8_t*, int);

}  // namespace viscera::bus
