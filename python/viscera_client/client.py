"""Client: sessions on viscerad over LCM (the protocol of docs/protocol.md).

    from viscera_client import Client
    with Client(key_file=None) as c:
        s = c.create(scene="cavity")          # the least loaded server with room
        c.send_pose(s, tool=0, position=(0, 0, 0.1))
        c.on_forces(s, lambda f, chan, t: print(f.force))
        c.pump(1.0)
        c.destroy(s)
"""
import os
import secrets
import time
from dataclasses import dataclass, field

import viscera_proto
from viscera_proto import session_reply_t, session_request_t

from .assessment import report_from_status
from .auth import MessageAuth
from .bus import Bus, make_header
from .directory import observe, pick_server

HEARTBEAT = "VISCERA_HEARTBEAT"
REQUEST = "VISCERA_SESSION_REQUEST"
REPLY = "VISCERA_SESSION_REPLY"
HEARTBEAT_PERIOD_S = 1.0  # viscerad's default: one listen of a little more hears everyone


def session_channel(prefix, session_id):
    """E.g. session_channel("POSE", 42) == "VISCERA_POSE_42"."""
    return f"VISCERA_{prefix}_{session_id}"


class VisceraError(Exception):
    """A server refused or did not answer. `result` is the reply's result (None: no reply)."""

    def __init__(self, message, result=None, server_id=""):
        super().__init__(message)
        self.result = result
        self.server_id = server_id


@dataclass
class SessionHandle:
    """What a client needs to drive a session (picklable: workers get a copy)."""
    session_id: int
    token: bytes
    server_id: str
    scene: str = ""
    rate_hz: float = 0.0
    tools: list = field(default_factory=list)
    frame_rate_hz: float = 0.0


class Client:
    """Requests, poses and subscriptions of one thread. `key_file`: sign and check MACs."""

    def __init__(self, url=None, key_file=None, auth=None):
        if auth is None and key_file:
            auth = MessageAuth.from_key_file(key_file)
        self.bus = Bus(url, auth)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.bus.close()

    def pump(self, timeout_s):
        return self.bus.pump(timeout_s)

    # --- servers -----------------------------------------------------------------------
    def servers(self, listen_s=HEARTBEAT_PERIOD_S + 0.2, timeout_s=None):
        """Every server heard, sorted by id (list of ServerInfo): listens `listen_s`, and
        longer, up to `timeout_s`, while none has been heard yet (one that is starting)."""
        heard = {}
        sub = self.bus.subscribe(HEARTBEAT, viscera_proto.heartbeat_t,
                                 lambda hb, chan, t: observe(heard, hb))
        start = time.monotonic()
        enough = start + listen_s
        deadline = start + max(listen_s, timeout_s or 0.0)
        try:
            while time.monotonic() < deadline and (time.monotonic() < enough or not heard):
                self.bus.pump(min(0.1, max(0.0, deadline - time.monotonic())))
        finally:
            self.bus.unsubscribe(sub)
        return [heard[k] for k in sorted(heard)]

    # --- requests ----------------------------------------------------------------------
    def request(self, request, timeout_s=2.0, collect_all=False, grace_s=0.3):
        """Publishes `request` and returns the replies with its request_id, the owner's
        first (as SessionClient::Request): at the first answer other than kUnknownSession,
        or after `grace_s` more for the rest (all of them with `collect_all`)."""
        replies = []

        def on_reply(reply, chan, t):
            if reply.request_id == request.request_id:
                replies.append(reply)

        sub = self.bus.subscribe(REPLY, session_reply_t, on_reply)
        try:
            self.bus.stamp(request, REQUEST)
            self.bus.publish(REQUEST, request)
            deadline = time.monotonic() + timeout_s
            extended = False
            while time.monotonic() < deadline:
                self.bus.pump(min(0.1, max(0.0, deadline - time.monotonic())))
                if not replies:
                    continue
                owner = any(r.result != session_reply_t.kUnknownSession for r in replies)
                if owner and not collect_all:
                    break
                if not extended:
                    deadline = min(deadline, time.monotonic() + grace_s)
                    extended = True
        finally:
            self.bus.unsubscribe(sub)
        replies.sort(key=lambda r: r.result == session_reply_t.kUnknownSession)
        return replies

    @staticmethod
    def make_request(command, session_id=0, token=b"", server_id=""):
        r = session_request_t()
        r.header = make_header(session_id, 0, token)
        r.request_id = secrets.randbits(62) | 1  # positive, never 0
        r.command = command
        r.server_id = server_id
        r.scene_name = ""
        r.scene_toml = ""
        r.rate_hz = 0.0
        r.skeleton_rate_hz = 0.0
        r.skin = ""
        r.frame_width = r.frame_height = 0
        r.frame_rate_hz = 0.0
        r.jpeg_quality = 0
        r.camera_eye = [0.0, 0.0, 0.0]
        r.camera_target = [0.0, 0.0, 0.0]
        r.camera_up = [0.0, 0.0, 1.0]
        r.camera_fov_deg = 60.0
        return r

    def _answer(self, request, timeout_s, what):
        replies = self.request(request, timeout_s)
        if not replies:
            raise VisceraError(f"no server answered {what} on {self.bus.url} within {timeout_s} s "
                              "(is viscerad running? a multicast route? the same key file?)")
        reply = replies[0]
        if reply.result != session_reply_t.kOk:
            raise VisceraError(f"server {reply.server_id} refused {what}: {reply.message}",
                              reply.result, reply.server_id)
        return reply

    def create(self, scene=None, scene_toml=None, server=None, rate_hz=0.0,
               frame_rate_hz=-1.0, skeleton_rate_hz=-1.0, frame_width=0, frame_height=0,
               skin="", jpeg_quality=0, timeout_s=5.0, servers=None, build_timeout_s=60.0):
        """Starts a session and returns its SessionHandle.

        `timeout_s` bounds hearing servers; the answer is awaited up to the longer of it and
        `build_timeout_s`: the server answers once the scene is built, at low priority, which
        takes seconds on a busy machine.

        `server` names the server; otherwise the least loaded server with room among
        `servers` (a list of ServerInfo; heard now when None) is asked. Frames and skeleton
        states are off unless asked (> 0; 0 = the server's default).
        Raises VisceraError when no server has room, none answers, or it refuses.
        """
        if (scene is None) == (scene_toml is None):
            raise ValueError("create needs a scene name or a scene_toml, not both")
        if not server:
            heard = self.servers(timeout_s=timeout_s) if servers is None else servers
            chosen = pick_server(heard)
            if chosen is None:
                raise VisceraError(
                    f"no server with room on {self.bus.url}: "
                    + (", ".join(f"{s.server_id} {s.sessions}/{s.max_sessions}" for s in heard)
                       or "none heard"))
            server = chosen.server_id
        r = self.make_request(session_request_t.kCreate, server_id=server)
        r.scene_name = scene or ""
        r.scene_toml = scene_toml or ""
        r.rate_hz = float(rate_hz)
        r.frame_rate_hz = float(frame_rate_hz)
        r.skeleton_rate_hz = float(skeleton_rate_hz)
        r.frame_width, r.frame_height = int(frame_width), int(frame_height)
        r.skin = skin
        r.jpeg_quality = int(jpeg_quality)
        reply = self._answer(r, max(timeout_s, build_timeout_s), f"the create on {server}")
        status = reply.sessions[0] if reply.num_sessions > 0 else None
        return SessionHandle(
            session_id=reply.header.session_id, token=bytes(reply.header.token),
            server_id=reply.server_id, scene=status.scene if status else (scene or "<inline>"),
            rate_hz=status.rate_hz if status else 0.0,
            tools=list(status.tool_names) if status else [],
            # the reply's status may predate the render thread: then the rate asked
            frame_rate_hz=(status.frame_rate_hz if status and status.frame_rate_hz > 0
                           else max(0.0, float(frame_rate_hz))))

    def command(self, session, command, timeout_s=2.0):
        """destroy, reset, pause or resume (session_request_t.k*): the reply's status."""
        r = self.make_request(command, session.session_id, session.token)
        reply = self._answer(r, timeout_s, f"command {command} for session {session.session_id}")
        return reply.sessions[0] if reply.num_sessions > 0 else None

    def keep_alive(self, session, timeout_s=2.0):
        """Renews the session's lease (protocol 4 on: a session hears nothing authentic for
        its lease, status lease_s, and is destroyed). Poses and commands renew it too."""
        if not hasattr(session_request_t, "kKeepAlive"):
            return None  # this protocol has no leases
        return self.command(session, session_request_t.kKeepAlive, timeout_s)

    def destroy(self, session, timeout_s=2.0):
        """Stops the session; returns its last status (counts of the whole session)."""
        return self.command(session, session_request_t.kDestroy, timeout_s)

    def status(self, session_id, timeout_s=2.0):
        """The status of one session (no token needed)."""
        reply = self._answer(self.make_request(session_request_t.kStatus, session_id), timeout_s,
                             f"the status of session {session_id}")
        return reply.sessions[0]

    def report(self, session_id, timeout_s=2.0):
        """The session's assessment so far (docs/assessment.md), as `viscera report --json`."""
        return report_from_status(self.status(session_id, timeout_s))

    def list(self, timeout_s=2.0):
        """The status of every session of every server that answers."""
        replies = self.request(self.make_request(session_request_t.kList), timeout_s,
                               collect_all=True, grace_s=0.5)
        return [s for r in replies for s in r.sessions]

    # --- streams -----------------------------------------------------------------------
    def send_pose(self, session, tool=0, position=(0.0, 0.0, 0.0),
                  orientation=(1.0, 0.0, 0.0, 0.0), jaw=1.0):
        """Publishes one tool pose; returns its header.seq (the force echoes it)."""
        channel = session_channel("POSE", session.session_id)
        p = viscera_proto.tool_pose_t()
        p.header = make_header(session.session_id, 0, session.token)
        self.bus.stamp(p, channel)
        p.tool = tool
        p.position = [float(x) for x in position]
        p.orientation = [float(x) for x in orientation]
        p.jaw = float(jaw)
        self.bus.publish(channel, p)
        return p.header.seq, p.header.utime

    def on_forces(self, session, handler):
        """handler(force_feedback_t, channel, recv_utime) for every force of the session."""
        return self.bus.subscribe(session_channel("FORCE", session.session_id),
                                  viscera_proto.force_feedback_t, handler)

    def on_status(self, session, handler):
        return self.bus.subscribe(session_channel("STATUS", session.session_id),
                                  viscera_proto.session_status_t, handler)

    def watch_frames(self, session):
        """Renews the session's frame lease (kWatchFrames, no token): the server draws frames only
        while someone renews it (viscerad --frame-lease, 5 s by default); send it every second or so."""
        if hasattr(session_request_t, "kWatchFrames"):
            r = self.make_request(session_request_t.kWatchFrames, session.session_id)
            self.bus.stamp(r, REQUEST)
            self.bus.publish(REQUEST, r)  # no wait for the reply

    def on_frames(self, session, handler):
        """handler(jpeg_frame_t, channel, recv_utime) for every frame; renews the frame lease once
        (watch_frames keeps it)."""
        self.watch_frames(session)
        return self.bus.subscribe(session_channel("FRAME", session.session_id),
                                  viscera_proto.jpeg_frame_t, handler)

    def on_skeleton(self, session, handler):
        return self.bus.subscribe(session_channel("SKELETON", session.session_id),
                                  viscera_proto.skeleton_state_t, handler)
