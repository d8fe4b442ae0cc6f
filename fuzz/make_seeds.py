#!/usr/bin/env python3
"""Writes the seed corpora of the message fuzz targets (fuzz/corpus/...): well-formed
viscera messages of every kind, each prefixed with the channel byte its target reads.
Usage: PYTHONPATH=build/python fuzz/make_seeds.py  (lcm-gen's Python types, from the build)."""
import os
import time

from viscera_proto import (header_t, heartbeat_t, jpeg_frame_t, session_reply_t,
                           session_request_t, session_status_t, skeleton_state_t, tool_pose_t)

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")


def header(session_id, seq, token=b""):
    h = header_t()
    h.version = header_t.kProtocolVersion
    h.session_id = session_id
    h.seq = seq
    h.utime = int(time.time() * 1e6)
    h.sender = 12345
    h.token = token
    h.token_len = len(token)
    h.mac = b""
    h.mac_len = 0
    return h


def request(command, session_id=0, **fields):
    r = session_request_t()
    r.header = header(session_id, command, bytes(range(16)) if session_id else b"")
    r.request_id = 1000 + command
    r.command = command
    r.server_id = "fuzz"
    r.scene_name = ""
    r.scene_toml = ""
    r.skin = ""
    r.camera_up = [0.0, 0.0, 1.0]
    r.camera_fov_deg = 60.0
    r.camera_eye = [0.0, -0.3, 0.3]
    r.camera_target = [0.0, 0.0, 0.0]
    r.frame_rate_hz = -1.0
    for k, v in fields.items():
        setattr(r, k, v)
    return r


def status():
    s = session_status_t()
    s.header = header(1, 3)
    s.server_id = "fuzz"
    s.scene = "hanging"
    s.tool_names = ["left", "right"]
    s.num_tools = 2
    s.state = session_status_t.kRunning
    s.skin = "parametric"
    s.last_error = "pose: jaw 5: must be within [0, 1]"
    return s


def write(target, name, channel_byte, message):
    d = os.path.join(root, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(bytes([channel_byte]) + message.encode())


Q = session_request_t
with open(os.path.join(os.path.dirname(root), "..", "tests", "e2e", "scenes", "push.toml")) as f:
    push = f.read()
write("fuzz_server_messages", "create_named", 0, request(Q.kCreate, scene_name="hanging"))
write("fuzz_server_messages", "create_inline", 0, request(Q.kCreate, scene_toml=push))
for name, command in [("pause", Q.kPause), ("resume", Q.kResume), ("reset", Q.kReset),
                      ("destroy", Q.kDestroy), ("status", Q.kStatus), ("keepalive", Q.kKeepAlive)]:
    write("fuzz_server_messages", name, 0, request(command, session_id=1))
write("fuzz_server_messages", "list", 0, request(Q.kList))
write("fuzz_server_messages", "camera", 0, request(Q.kCamera, session_id=1))
p = tool_pose_t()
p.header = header(1, 7, bytes(range(16)))
p.tool = 0
p.position = [0.0, 0.0, 0.1]
p.orientation = [1.0, 0.0, 0.0, 0.0]
p.jaw = 0.5
write("fuzz_server_messages", "pose", 1, p)
write("fuzz_server_messages", "pose_unknown_session", 2, p)

f = jpeg_frame_t()
f.header = header(1, 0)
f.width, f.height = 2, 2
f.data = bytes([0xFF, 0xD8, 0xFF, 0xD9])
f.size = len(f.data)
write("fuzz_client_messages", "frame", 1, f)
hb = heartbeat_t()
hb.header = header(0, 0)
hb.server_id = "fuzz"
hb.num_sessions, hb.max_sessions = 1, 4
write("fuzz_client_messages", "heartbeat", 0, hb)
reply = session_reply_t()
reply.header = header(1, 0)
reply.request_id = 1007
reply.command = Q.kStatus
reply.result = session_reply_t.kOk
reply.message = ""
reply.server_id = "fuzz"
reply.sessions = [status()]
reply.num_sessions = 1
write("fuzz_client_messages", "reply_status", 2, reply)
write("fuzz_client_messages", "status", 3, status())
k = skeleton_state_t()
k.header = header(1, 0)
k.step, k.sim_time = 10, 0.01
k.points = [[0.01 * i, 0.0, 0.0] for i in range(4)]
k.num_points = len(k.points)
k.spheres = [[0.005 + 0.01 * i, 0.0, 0.0] for i in range(3)]
k.num_spheres = len(k.spheres)
k.sphere_radius = 0.01
write("fuzz_client_messages", "skeleton", 4, k)
# regressions: a frame claiming 2^31 - 1 bytes (LCM 1.3.1 sized the array before checking it)
huge = bytearray(f.encode())
huge[-4 - len(f.data):-len(f.data)] = (0x7FFFFFFF).to_bytes(4, "big")
with open(os.path.join(root, "fuzz_client_messages", "regression_frame_huge_size"), "wb") as out:
    out.write(bytes([1]) + bytes(huge))
