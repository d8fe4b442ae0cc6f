"""Fast partial decoding of the two messages a load test receives by the thousand.

lcm-gen's Python decode builds every field of force_feedback_t (about 30 numbers) in pure
Python; a load tester at 1 kHz per session needs only the sequence numbers and times.
These read them at their fixed offsets and check the type's fingerprint, so a client on
the same cores as the server spends its time sending poses, not decoding.
tests/python/fast_test.py checks them against the full decode.
"""
import struct

import viscera_proto

_FORCE_FP = viscera_proto.force_feedback_t._get_packed_fingerprint()
_FRAME_FP = viscera_proto.jpeg_frame_t._get_packed_fingerprint()
# version, session_id, seq, utime, [sender: protocol 4 on], token_len
_HEADER = struct.Struct(">hqqq" + ("q" if "sender" in viscera_proto.header_t.__slots__ else "") + "i")
# force_feedback_t after its header: tool, step, sim_time, force[3], torque[3],
# stiffness[3][3], tip[3], then pose_seq and pose_utime
_FORCE_BODY = struct.Struct(">iqd" + "d" * 18 + "qq")
# jpeg_frame_t after its header: step, sim_time, snapshot_utime
_FRAME_BODY = struct.Struct(">qdq")


def _header(data, fingerprint):
    """(version, session_id, seq, utime, offset after the header), or None."""
    if data[:8] != fingerprint or len(data) < 8 + _HEADER.size + 4:
        return None
    fields = _HEADER.unpack_from(data, 8)
    version, session_id, seq, utime, token_len = fields[:4] + fields[-1:]
    offset = 8 + _HEADER.size + token_len
    if token_len < 0 or offset + 4 > len(data):
        return None
    (mac_len,) = struct.unpack_from(">i", data, offset)
    offset += 4 + mac_len
    if mac_len < 0 or offset > len(data):
        return None
    return version, session_id, seq, utime, offset


def force_echo(data):
    """(version, seq, tool, pose_seq, pose_utime) of an encoded force_feedback_t, or None
    when the datagram is not one (wrong type or truncated)."""
    h = _header(data, _FORCE_FP)
    if h is None or h[4] + _FORCE_BODY.size + 3 > len(data):
        return None
    body = _FORCE_BODY.unpack_from(data, h[4])
    return h[0], h[2], body[0], body[-2], body[-1]


def frame_times(data):
    """(version, seq, utime, snapshot_utime) of an encoded jpeg_frame_t, or None."""
    h = _header(data, _FRAME_FP)
    if h is None or h[4] + _FRAME_BODY.size > len(data):
        return None
    _, _, snapshot_utime = _FRAME_BODY.unpack_from(data, h[4])
    return h[0], h[2], h[3], snapshot_utime
