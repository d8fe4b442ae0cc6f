"""Client: sessions on viscerad over LCM (the protocol of docs/protocol.md).

    from viscera_client import Client, Rate
    with Client() as client:                      # key_file="psk" on a signed bus
        with client.session("cavity") as s:       # destroyed when the block ends
            rate = Rate(100)
            for i in range(100):
                s.send_pose("right", (0.0, 0.02, 0.10), jaw=1.0)
                rate.sleep(client)                # paces, and handles forces meanwhile
            print(s.latest_force("right"))        # numpy array (N)

The reference of every public name: docs/python.md.
"""
from __future__ import annotations

import secrets
import time
from dataclasses import dataclass, field
from typing import Any, Callable, List, Optional, Sequence, Tuple

import viscera_proto
from viscera_proto import session_reply_t, session_request_t

from . import validate
from .assessment import report_from_status
from .auth import MessageAuth
from .bus import Bus, make_header
from .directory import ServerInfo, observe, pick_server
from .session import Session, Status, wait_until
from .validate import ToolRef

HEARTBEAT = "VISCERA_HEARTBEAT"
REQUEST = "VISCERA_SESSION_REQUEST"
REPLY = "VISCERA_SESSION_REPLY"
HEARTBEAT_PERIOD_S = 1.0  # viscerad's default: one listen of a little more hears everyone
MAX_RATE_HZ = 1000.0      # viscerad's default --max-rate
COMMAND_NAMES = {session_request_t.kDestroy: "destroy", session_request_t.kReset: "reset",
                 session_request_t.kPause: "pause", session_request_t.kResume: "resume",
                 session_request_t.kCamera: "camera", session_request_t.kStatus: "status"}


def session_channel(prefix: str, session_id: int) -> str:
    """E.g. session_channel("POSE", 42) == "VISCERA_POSE_42"."""
    return f"VISCERA_{prefix}_{session_id}"


class VisceraError(Exception):
    """A server refused or did not answer. `result` is the reply's result (None: no reply),
    `server_id` the server that answered ("" if none)."""

    def __init__(self, message: str, result: Optional[int] = None, server_id: str = ""):
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
    tools: List[str] = field(default_factory=list)
    frame_rate_hz: float = 0.0


class Client:
    """Requests, poses and subscriptions of one thread (one Client per thread or process).
    `url`: the LCM URL (default $LCM_DEFAULT_URL, else udpm with ttl=0); `key_file`: sign
    every message and check every MAC with this pre-shared key. As a context manager it
    destroys the sessions it made with session() that are still running, then closes."""

    def __init__(self, url: Optional[str] = None, key_file: Optional[str] = None,
                 auth: Optional[MessageAuth] = None):
        if auth is None and key_file:
            auth = MessageAuth.from_key_file(key_file)
        self.bus = Bus(url, auth)
        self._sessions: List[Session] = []

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def close(self) -> None:
        """Destroys the sessions session() made that still run, and closes the bus."""
        for s in self._sessions:
            try:
                s.destroy()
            except VisceraError:
                pass  # gone already (lease, server stopped): nothing left to free
        self._sessions.clear()
        self.bus.close()

    def pump(self, timeout_s: float) -> int:
        """Waits up to `timeout_s` for the first message, then handles what is queued, and
        returns at once: the number handled. To wait a given time, use pump_for()."""
        return self.bus.pump(timeout_s)

    def pump_for(self, seconds: float) -> int:
        """Handles messages (forces, status, frames to their handlers) for `seconds` of wall
        time, however many arrive; returns the number handled."""
        handled = 0
        end = time.monotonic() + max(0.0, seconds)
        while True:
            left = end - time.monotonic()
            if left <= 0:
                return handled
            handled += self.bus.pump(left)

    def spin_until(self, predicate: Callable[[], bool], timeout_s: float) -> bool:
        """Handles messages until predicate() is true (checked after each batch) or
        `timeout_s` passed; returns whether it became true."""
        return wait_until(predicate, self.bus.pump, timeout_s)

    # --- servers -----------------------------------------------------------------------
    def servers(self, listen_s: float = HEARTBEAT_PERIOD_S + 0.2,
                timeout_s: Optional[float] = None) -> List[ServerInfo]:
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
    def request(self, request: session_request_t, timeout_s: float = 2.0,
                collect_all: bool = False, grace_s: float = 0.3) -> List[session_reply_t]:
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
    def make_request(command: int, session_id: int = 0, token: bytes = b"",
                     server_id: str = "") -> session_request_t:
        """A session_request_t of `command` with every field set (a fresh request_id)."""
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

    def create(self, scene: Optional[str] = None, scene_toml: Optional[str] = None,
               server: Optional[str] = None, rate_hz: float = 0.0, frame_rate_hz: float = -1.0,
               skeleton_rate_hz: float = -1.0, frame_width: int = 0, frame_height: int = 0,
               skin: str = "", jpeg_quality: int = 0, timeout_s: float = 5.0,
               servers: Optional[List[ServerInfo]] = None,
               build_timeout_s: float = 60.0) -> SessionHandle:
        """Starts a session and returns its SessionHandle.

        `timeout_s` bounds hearing servers; the answer is awaited up to the longer of it and
        `build_timeout_s`: the server answers once the scene is built, at low priority, which
        takes seconds on a busy machine.

        `server` names the server; otherwise the least loaded server with room among
        `servers` (a list of ServerInfo; heard now when None) is asked. Frames and skeleton
        states are off unless asked (> 0; 0 = the server's default).
        Raises VisceraError when no server has room, none answers, or it refuses;
        ValueError for a missing scene or a rate out of range.
        """
        if scene is None and scene_toml is None:
            raise ValueError("create needs a scene: a name in the server's scene directory "
                             "(scene=\"cavity\") or a scene's TOML text (scene_toml=...)")
        if scene is not None and scene_toml is not None:
            raise ValueError("create takes a scene name or a scene_toml, not both")
        if not 0.0 <= float(rate_hz) <= MAX_RATE_HZ:
            raise ValueError(f"rate_hz {rate_hz:g} must be within 0..{MAX_RATE_HZ:g} Hz "
                             "(0 = the scene's rate; servers cap it at their --max-rate)")
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

    def session(self, scene: Optional[str] = None, **create_args: Any) -> Session:
        """Creates a session (the arguments of create()) and returns it as a Session: use it
        in a `with` block and it is destroyed when the block ends; the Client's own exit
        destroys it otherwise."""
        s = Session(self, self.create(scene, **create_args))
        self._sessions.append(s)
        return s

    def command(self, session: SessionHandle, command: int,
                timeout_s: float = 2.0) -> Optional[Status]:
        """destroy, reset, pause or resume (session_request_t.k*): the reply's status."""
        r = self.make_request(command, session.session_id, session.token)
        reply = self._answer(r, timeout_s, f"{COMMAND_NAMES.get(command, command)} of session "
                                           f"{session.session_id}")
        return Status.from_message(reply.sessions[0]) if reply.num_sessions > 0 else None

    def camera(self, session: SessionHandle, eye: Sequence[float], target: Sequence[float],
               up: Sequence[float] = (0.0, 0.0, 1.0), fov_deg: float = 60.0,
               timeout_s: float = 2.0) -> Optional[Status]:
        """Points the session's laparoscope (its frames) from `eye` at `target` (m)."""
        e = validate.position(eye, "camera eye")
        t = validate.position(target, "camera target")
        u = validate.vector(up, 3, "camera up")
        if float(((t - e) ** 2).sum()) < 1e-12:
            raise validate.PoseError(f"camera eye and target are the same point {e.tolist()}")
        if not 1.0 < float(fov_deg) < 179.0:
            raise validate.PoseError(f"camera fov_deg {fov_deg:g} must be within (1, 179)")
        r = self.make_request(session_request_t.kCamera, session.session_id, session.token)
        r.camera_eye, r.camera_target, r.camera_up = e.tolist(), t.tolist(), u.tolist()
        r.camera_fov_deg = float(fov_deg)
        reply = self._answer(r, timeout_s, f"the camera of session {session.session_id}")
        return Status.from_message(reply.sessions[0]) if reply.num_sessions > 0 else None

    def keep_alive(self, session: SessionHandle, timeout_s: float = 2.0) -> Optional[Status]:
        """Renews the session's lease (protocol 4 on: a session hears nothing authentic for
        its lease, status lease_s, and is destroyed). Poses and commands renew it too."""
        if not hasattr(session_request_t, "kKeepAlive"):
            return None  # this protocol has no leases
        return self.command(session, session_request_t.kKeepAlive, timeout_s)

    def destroy(self, session: SessionHandle, timeout_s: float = 2.0) -> Optional[Status]:
        """Stops the session; returns its last status (counts of the whole session)."""
        return self.command(session, session_request_t.kDestroy, timeout_s)

    def status(self, session_id: int, timeout_s: float = 2.0) -> Status:
        """The status of one session (no token needed)."""
        reply = self._answer(self.make_request(session_request_t.kStatus, session_id), timeout_s,
                             f"the status of session {session_id}")
        return Status.from_message(reply.sessions[0])

    def report(self, session_id: int, timeout_s: float = 2.0) -> dict:
        """The session's assessment so far (docs/assessment.md), as `viscera report --json`."""
        return report_from_status(self.status(session_id, timeout_s).raw)

    def list(self, timeout_s: float = 2.0) -> List[Status]:
        """The status of every session of every server that answers."""
        replies = self.request(self.make_request(session_request_t.kList), timeout_s,
                               collect_all=True, grace_s=0.5)
        return [Status.from_message(s) for r in replies for s in r.sessions]

    # --- streams -----------------------------------------------------------------------
    def send_pose(self, session: SessionHandle, tool: ToolRef = 0,
                  position: Sequence[float] = (0.0, 0.0, 0.0),
                  orientation: Sequence[float] = (1.0, 0.0, 0.0, 0.0),
                  jaw: float = 1.0) -> Tuple[int, int]:
        """Publishes one target pose of `tool` (a name of session.tools or an index): tip
        `position` (m), `orientation` quaternion (w, x, y, z), `jaw` within [0, 1] (1 open).
        Every value is checked here first (validate.PoseError, a ValueError, naming it).
        Returns (header.seq, header.utime): the force that answers echoes both."""
        if session.tools:
            index = validate.tool_index(tool, session.tools, session.session_id)
        elif isinstance(tool, int) and tool >= 0:
            index = tool  # a handle made by hand, without the tool names: the server checks
        else:
            raise validate.PoseError(f"tool {tool!r}: this handle has no tool names; give an index")
        pos = validate.position(position)
        quat = validate.orientation(orientation)
        opening = validate.jaw(jaw)
        channel = session_channel("POSE", session.session_id)
        p = viscera_proto.tool_pose_t()
        p.header = make_header(session.session_id, 0, session.token)
        self.bus.stamp(p, channel)
        p.tool = index
        p.position = pos.tolist()
        p.orientation = quat.tolist()
        p.jaw = opening
        self.bus.publish(channel, p)
        return p.header.seq, p.header.utime

    def on_forces(self, session: SessionHandle,
                  handler: Callable[[Any, str, int], None]) -> Any:
        """handler(force_feedback_t, channel, recv_utime) for every force of the session;
        returns the subscription (bus.unsubscribe)."""
        return self.bus.subscribe(session_channel("FORCE", session.session_id),
                                  viscera_proto.force_feedback_t, handler)

    def on_status(self, session: SessionHandle,
                  handler: Callable[[Any, str, int], None]) -> Any:
        """handler(session_status_t, channel, recv_utime) for every status the session
        publishes (4 Hz by default); returns the subscription."""
        return self.bus.subscribe(session_channel("STATUS", session.session_id),
                                  viscera_proto.session_status_t, handler)

    def watch_frames(self, session: SessionHandle) -> None:
        """Renews the session's frame lease (kWatchFrames, no token): the server draws frames only
        while someone renews it (viscerad --frame-lease, 5 s by default); send it every second or so."""
        if hasattr(session_request_t, "kWatchFrames"):
            r = self.make_request(session_request_t.kWatchFrames, session.session_id)
            self.bus.stamp(r, REQUEST)
            self.bus.publish(REQUEST, r)  # no wait for the reply

    def on_frames(self, session: SessionHandle,
                  handler: Callable[[Any, str, int], None]) -> Any:
        """handler(jpeg_frame_t, channel, recv_utime) for every frame (create the session
        with frame_rate_hz > 0); renews the frame lease once (watch_frames keeps it); returns
        the subscription."""
        self.watch_frames(session)
        return self.bus.subscribe(session_channel("FRAME", session.session_id),
                                  viscera_proto.jpeg_frame_t, handler)

    def on_skeleton(self, session: SessionHandle,
                    handler: Callable[[Any, str, int], None]) -> Any:
        """handler(skeleton_state_t, channel, recv_utime) for every skeleton state (create
        with skeleton_rate_hz > 0); returns the subscription."""
        return self.bus.subscribe(session_channel("SKELETON", session.session_id),
                                  viscera_proto.skeleton_state_t, handler)
