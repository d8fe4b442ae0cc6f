#include "bus/wire_counts.h"

#include <viscera_proto/force_feedback_t.hpp>
#include <viscera_proto/heartbeat_t.hpp>
#include <viscera_proto/jpeg_frame_t.hpp>
#include <viscera_proto/session_reply_t.hpp>
#include <viscera_proto/session_request_t.hpp>
#include <viscera_proto/session_status_t.hpp>
#include <viscera_proto/skeleton_state_t.hpp>
#include <viscera_proto/step_record_t.hpp>
#include <viscera_proto/tool_pose_t.hpp>

namespace viscera::bus {
namespace {

// Reads an encoded message front to back, as far as its counts go; any overrun latches !ok.
// Fixed-size fields are skipped by their wire size (LCM: big-endian, no padding).
class WireCursor {
 public:
  WireCursor(const uint8_t* data, int size) : p_(data), left_(size) {}

  bool ok() const { return ok_; }

  void Skip(int64_t bytes) {
    if (!ok_ || bytes < 0 || bytes > left_) {
      ok_ = false;
      return;
    }
    p_ += bytes;
    left_ -= static_cast<int>(bytes);
  }

  /// A count; refused when negative or when `min_element_bytes` each would not fit.
  int32_t Count(int min_element_bytes) {
    const int32_t n = Int32();
    if (ok_ && (n < 0 || static_cast<int64_t>(n) * min_element_bytes > left_)) ok_ = false;
    return ok_ ? n : 0;
  }

  /// A count and its elements, each exactly `element_bytes` on the wire.
  void FixedArray(int element_bytes) {
    Skip(static_cast<int64_t>(Count(element_bytes)) * element_bytes);
  }

  /// An LCM string: int32 length (including its NUL, so at least 1), then the bytes. The
  /// generated decode assigns length - 1 bytes: a length of 0 would ask for SIZE_MAX.
  void String() {
    const int32_t n = Int32();
    if (n < 1) ok_ = false;
    Skip(n);
  }

  void Header() {
    Skip(2 + 8 + 8 + 8 + 8);  // version, session_id, seq, utime, sender
    FixedArray(1);            // token
    FixedArray(1);            // mac
  }

  void Fingerprint() { Skip(8); }

 private:
  int32_t Int32() {
    if (!ok_ || left_ < 4) {
      ok_ = false;
      return 0;
    }
    const uint32_t v = (uint32_t{p_[0]} << 24) | (uint32_t{p_[1]} << 16) | (uint32_t{p_[2]} << 8) |
                       uint32_t{p_[3]};
    p_ += 4;
    left_ -= 4;
    return static_cast<int32_t>(v);
  }

  const uint8_t* p_;
  int left_;
  bool ok_ = true;
};

constexpr int kStringMinBytes = 5;  // length and NUL
// tool_target_t: tip[3], orientation[4], jaw (doubles), active (boolean), pose_seq
constexpr int kToolTargetBytes = 8 * 8 + 1 + 8;
// the smallest header_t (empty token and MAC) and session_status_t on the wire
constexpr int kHeaderMinBytes = 2 + 4 * 8 + 4 + 4;
constexpr int kStatusMinBytes = kHeaderMinBytes + 4 * kStringMinBytes + 4;  // 4 strings, num_tools

// A count of strings and the strings.
void Strings(WireCursor& c) {
  const int32_t n = c.Count(kStringMinBytes);
  for (int32_t i = 0; i < n && c.ok(); ++i) c.String();
}

// session_status_t's running_ fields, in proto/session_status_t.lcm's order
void Running(WireCursor& c) {
  c.Skip(4 + 2 * 8);  // running_segments, segment_length, coverage
  c.FixedArray(4);    // missed
  // reversals, grasps, regrasps, slips; path_length; instrument_collisions; out_of_view_time,
  // time, max_grip, max_pressure, max_traction, max_dose
  c.Skip(4 * 4 + 8 + 4 + 6 * 8);
  // events: kinds and tools (strings), segments (int32), times and values (doubles)
  const int32_t events = c.Count(2 * kStringMinBytes + 4 + 2 * 8);
  for (int32_t i = 0; i < events && c.ok(); ++i) c.String();
  c.Skip(static_cast<int64_t>(events) * 4);
  for (int32_t i = 0; i < events && c.ok(); ++i) c.String();
  c.Skip(static_cast<int64_t>(events) * 2 * 8);
  c.FixedArray(4);        // damaged
  c.Skip(3 * 8 + 1);      // run_length, estimate_length, estimate_error; passed
  Strings(c);             // failed
  c.Skip(9 * 8 + 3 * 4);  // the thresholds and pass marks
}

// session_status_t, nested (no fingerprint): the fields in proto/session_status_t.lcm's order
void Status(WireCursor& c) {
  c.Header();
  c.String();  // server_id
  c.String();  // scene
  const int32_t tools = c.Count(kStringMinBytes);
  for (int32_t i = 0; i < tools && c.ok(); ++i) c.String();
  // state; sim_time, steps, rate_hz, achieved_rate_hz, deadline_misses; four floats; contacts;
  // energy, poses, rejected, replayed, lease_s, lease_left_s, recoveries, idle_events
  c.Skip(1 + 5 * 8 + 4 * 4 + 4 + 8 * 8);
  c.String();  // skin
  // frame_width, frame_height; frame_rate_hz, achieved_frame_rate_hz, frames, frames_dropped;
  // skin_ms, render_ms, encode_ms; frame_bytes
  c.Skip(2 * 4 + 4 * 8 + 3 * 4 + 4);
  c.String();  // last_error
  // the assessment, per tool: eight double arrays and four int32 arrays of num_tools each
  c.Skip(static_cast<int64_t>(tools) * (8 * 8 + 4 * 4));
  const int32_t targets = c.Count(kStringMinBytes);
  for (int32_t i = 0; i < targets && c.ok(); ++i) c.String();
  c.Skip(static_cast<int64_t>(targets) * 3 * 8);  // exposed, max exposed, time to expose
  c.Skip(4 * 8);  // traction_force, traction_hold, regrasp_window, exposed_fraction
  // messages_dropped, nonfinite_dropped, record_failures, unconverged_solves
  c.Skip(4 * 8);
  Running(c);
}

// Messages whose only arrays are the header's (and no strings).
bool HeaderOnly(const uint8_t* data, int size) {
  WireCursor c(data, size);
  c.Fingerprint();
  c.Header();
  return c.ok();
}

}  // namespace

template <>
bool ArrayCountsFit<viscera_proto::jpeg_frame_t>(const uint8_t* data, int size) {
  WireCursor c(data, size);
  c.Fingerprint();
  c.Header();
  c.Skip(4 * 8 + 3 * 4 + 2 * 4);  // step .. dropped; skin/render/encode ms; width, height
  c.FixedArray(1);                // data[size]
  return c.ok();
}

template <>
bool ArrayCountsFit<viscera_proto::skeleton_state_t>(const uint8_t* data, int size) {
  WireCursor c(data, size);
  c.Fingerprint();
  c.Header();
  c.Skip(8 + 8);        // step, sim_time
  c.FixedArray(3 * 8);  // points[num_points][3]
  c.FixedArray(3 * 8);  // spheres[num_spheres][3]
  return c.ok();
}

template <>
bool ArrayCountsFit<viscera_proto::session_status_t>(const uint8_t* data, int size) {
  WireCursor c(data, size);
  c.Fingerprint();
  Status(c);
  return c.ok();
}

template <>
bool ArrayCountsFit<viscera_proto::session_reply_t>(const uint8_t* data, int size) {
  WireCursor c(data, size);
  c.Fingerprint();
  c.Header();
  c.Skip(8 + 1 + 1);  // request_id, command, result
  c.String();         // message
  c.String();         // server_id
  const int32_t sessions = c.Count(kStatusMinBytes);
  for (int32_t i = 0; i < sessions && c.ok(); ++i) Status(c);
  return c.ok();
}

template <>
bool ArrayCountsFit<viscera_proto::step_record_t>(const uint8_t* data, int size) {
  WireCursor c(data, size);
  c.Fingerprint();
  c.Header();
  c.Skip(1 + 8);                   // kind, step
  c.FixedArray(kToolTargetBytes);  // tools[num_tools]
  return c.ok();
}

template <>
bool ArrayCountsFit<viscera_proto::session_request_t>(const uint8_t* data, int size) {
  WireCursor c(data, size);
  c.Fingerprint();
  c.Header();
  c.Skip(8 + 1);  // request_id, command
  c.String();     // server_id
  c.String();     // scene_name
  c.String();     // scene_toml
  c.Skip(8 + 8);  // rate_hz, skeleton_rate_hz
  c.String();     // skin
  return c.ok();
}

template <>
bool ArrayCountsFit<viscera_proto::heartbeat_t>(const uint8_t* data, int size) {
  WireCursor c(data, size);
  c.Fingerprint();
  c.Header();
  c.String();  // server_id
  // num_sessions .. min_record_free_bytes: eleven 4-byte and fourteen 8-byte fields
  c.Skip(11 * 4 + 14 * 8);
  c.String();         // capacity
  c.Skip(4 + 8 + 8);  // cores, not_ours, unconverged_solves
  return c.ok();
}

template <>
bool ArrayCountsFit<viscera_proto::tool_pose_t>(const uint8_t* data, int size) {
  return HeaderOnly(data, size);
}
template <>
bool ArrayCountsFit<viscera_proto::force_feedback_t>(const uint8_t* data, int size) {
  return HeaderOnly(data, size);
}

bool CountsFitForFingerprint(const uint8_t* data, int size) {
  if (size < 8) return false;
  uint64_t hash = 0;
  for (int i = 0; i < 8; ++i) hash = (hash << 8) | data[i];
  const auto is = [hash](int64_t type_hash) { return hash == static_cast<uint64_t>(type_hash); };
  using namespace viscera_proto;
  if (is(jpeg_frame_t::getHash())) return ArrayCountsFit<jpeg_frame_t>(data, size);
  if (is(skeleton_state_t::getHash())) return ArrayCountsFit<skeleton_state_t>(data, size);
  if (is(session_status_t::getHash())) return ArrayCountsFit<session_status_t>(data, size);
  if (is(session_reply_t::getHash())) return ArrayCountsFit<session_reply_t>(data, size);
  if (is(step_record_t::getHash())) return ArrayCountsFit<step_record_t>(data, size);
  if (is(session_request_t::getHash())) return ArrayCountsFit<session_request_t>(data, size);
  if (is(heartbeat_t::getHash())) return ArrayCountsFit<heartbeat_t>(data, size);
  if (is(tool_pose_t::getHash())) return ArrayCountsFit<tool_pose_t>(data, size);
  if (is(force_feedback_t::getHash())) return ArrayCountsFit<force_feedback_t>(data, size);
  return HeaderOnly(data, size);
}

}  // namespace viscera::bus
