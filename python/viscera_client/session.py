"""A session as a Python object: a context manager that destroys it on exit, tools by name,
the latest force per tool as a numpy array, its status as a dataclass, and commands.

    from viscera_client import Client, Rate
    with Client() as client, client.session("cavity") as s:
        rate = Rate(100)
        for i in range(200):
            s.send_pose("right", (0.0, 0.02, 0.10 - 0.0002 * i), jaw=1.0)
            rate.sleep(client)          # paces at 100 Hz, handling forces meanwhile
        print(s.latest_force("right"), s.status().state)
"""
from __future__ import annotations

import enum
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, Dict, List, Optional, Sequence

import numpy as np

import viscera_proto
from viscera_proto import session_request_t

from . import validate
from .validate import ToolRef

if TYPE_CHECKING:  # pragma: no cover
    from .client import Client, SessionHandle


class SessionState(enum.IntEnum):
    """A session's state (session_status_t.state)."""
    RUNNING = 1   #: stepping
    PAUSED = 2    #: paused by its client: no steps until resumed
    FAULTED = 3   #: the mechanics thread failed; Status.last_error says why
    STOPPED = 4   #: destroyed (or its lease ran out): the last status it sends
    UNKNOWN = 0   #: a state this client does not know (a newer server)

    @classmethod
    def of(cls, value: int) -> "SessionState":
        """The state of a status's integer (UNKNOWN when it is not one of these)."""
        try:
            return cls(int(value))
        except ValueError:
            return cls.UNKNOWN


@dataclass
class Status:
    """How a session is doing (a session_status_t, docs/protocol.md). The fields most use
    are here; every other field of the message reads through as an attribute (status.energy,
    status.tool_force_max, ...) and `raw` is the message itself."""
    session_id: int
    server_id: str
    scene: str
    tools: List[str]
    state: SessionState
    sim_time: float          #: simulated time (s)
    steps: int
    rate_hz: float           #: configured mechanics rate (Hz)
    achieved_rate_hz: float  #: over about the last second (Hz)
    deadline_misses: int
    poses: int               #: poses accepted
    rejected: int            #: messages of this session dropped as invalid
    lease_left_s: float      #: the session ends when this reaches 0 without client traffic
    last_error: str
    #: linear solves accepted short of their tolerance since the session started (count)
    unconverged_solves: int = 0
    raw: Any = field(repr=False, default=None)

    @classmethod
    def from_message(cls, msg: "viscera_proto.session_status_t") -> "Status":
        """The Status of a received session_status_t."""
        return cls(session_id=msg.header.session_id, server_id=msg.server_id, scene=msg.scene,
                   tools=list(msg.tool_names), state=SessionState.of(msg.state),
                   sim_time=msg.sim_time, steps=msg.steps, rate_hz=msg.rate_hz,
                   achieved_rate_hz=msg.achieved_rate_hz, deadline_misses=msg.deadline_misses,
                   poses=msg.poses, rejected=msg.rejected, lease_left_s=msg.lease_left_s,
                   last_error=msg.last_error,
                   unconverged_solves=getattr(msg, "unconverged_solves", 0), raw=msg)

    def __getattr__(self, name: str) -> Any:
        # only called for names the dataclass lacks: the message's other fields
        raw = self.__dict__.get("raw")
        if raw is not None and not name.startswith("_") and hasattr(raw, name):
            return getattr(raw, name)
        raise AttributeError(f"Status has no field '{name}'")


@dataclass
class Force:
    """The latest force feedback of one tool (force_feedback_t), as numpy arrays."""
    force: np.ndarray        #: on the hand (N), shape (3,)
    torque: np.ndarray       #: (N m), shape (3,)
    stiffness: np.ndarray    #: local stiffness for a 1 kHz device loop (N/m), shape (3, 3)
    tip: np.ndarray          #: simulated tool tip (m), shape (3,)
    sim_time: float          #: simulated time of the step that computed it (s)
    pose_seq: int            #: header.seq of the pose it answers (-1: none yet)
    clamped: bool            #: limited to the device-safe maximum
    grasping: bool           #: the jaws hold the intestine

    @classmethod
    def from_message(cls, f: "viscera_proto.force_feedback_t") -> "Force":
        """The Force of a received force_feedback_t."""
        return cls(force=np.array(f.force, dtype=float), torque=np.array(f.torque, dtype=float),
                   stiffness=np.array(f.stiffness, dtype=float).reshape(3, 3),
                   tip=np.array(f.tip, dtype=float), sim_time=f.sim_time, pose_seq=f.pose_seq,
                   clamped=bool(f.clamped), grasping=bool(f.grasping))


class Rate:
    """Paces a loop at `hz`, as ROS's rospy.Rate: `sleep()` waits until the next tick (an
    absolute schedule, so the loop's own work does not slow it). With a client, the wait
    handles its messages (forces, status) instead of sleeping blind. A loop that falls more
    than a period behind skips the missed ticks rather than bursting; `missed` counts them."""

    def __init__(self, hz: float):
        if not hz > 0:
            raise ValueError(f"Rate needs a positive rate in Hz, got {hz!r}")
        self.period = 1.0 / float(hz)
        self.next = time.monotonic() + self.period
        self.missed = 0

    def sleep(self, client: Optional["Client"] = None) -> None:
        """Waits until the next tick, handling `client`'s messages meanwhile."""
        now = time.monotonic()
        if now > self.next + self.period:
            behind = int((now - self.next) / self.period)
            self.missed += behind
            self.next += behind * self.period
        if client is not None:
            client.pump_for(self.next - time.monotonic())
        else:
            time.sleep(max(0.0, self.next - time.monotonic()))
        self.next += self.period


class Session:
    """One running session, driven through its Client. Made by Client.session(); as a
    context manager it is destroyed on exit (also when the block raises)."""

    def __init__(self, client: "Client", handle: "SessionHandle"):
        self.client = client
        self.handle = handle
        self._forces: Dict[int, Force] = {}
        self._destroyed = False
        self._subscription = client.on_forces(handle, self._on_force)

    # --- who it is ----------------------------------------------------------------------
    @property
    def id(self) -> int:
        """The session id (as viscera's CLI prints it)."""
        return self.handle.session_id

    @property
    def server_id(self) -> str:
        """The server running it."""
        return self.handle.server_id

    @property
    def tools(self) -> List[str]:
        """Tool names, in index order (the scene's [[tool]] names)."""
        return list(self.handle.tools)

    @property
    def rate_hz(self) -> float:
        """Its mechanics rate (Hz)."""
        return self.handle.rate_hz

    def tool_index(self, tool: ToolRef) -> int:
        """The index of a tool given by name or index (PoseError if it has no such tool)."""
        return validate.tool_index(tool, self.handle.tools, self.id)

    # --- poses and forces ---------------------------------------------------------------
    def send_pose(self, tool: ToolRef, position: Sequence[float], jaw: float = 1.0,
                  orientation: Sequence[float] = (1.0, 0.0, 0.0, 0.0)) -> int:
        """Publishes a target pose of `tool` (name or index): tip `position` (m, 3 numbers),
        `jaw` opening within [0, 1] (1 open), `orientation` a quaternion (w, x, y, z).
        Checked here first (PoseError). Returns the pose's header.seq (forces echo it)."""
        seq, _ = self.client.send_pose(self.handle, tool, position, orientation, jaw)
        return seq

    def latest_force(self, tool: ToolRef) -> Optional[np.ndarray]:
        """The latest force on the hand of `tool` (N, numpy array of 3), or None before the
        first force arrived. Forces arrive while the client pumps (pump_for, Rate.sleep)."""
        f = self._forces.get(self.tool_index(tool))
        return None if f is None else f.force.copy()

    def latest_feedback(self, tool: ToolRef) -> Optional[Force]:
        """The latest whole force feedback of `tool` (torque, stiffness, tip, ...), or None."""
        return self._forces.get(self.tool_index(tool))

    def _on_force(self, f: "viscera_proto.force_feedback_t", channel: str, recv_utime: int) -> None:
        self._forces[f.tool] = Force.from_message(f)

    # --- commands -----------------------------------------------------------------------
    def status(self, timeout_s: float = 2.0) -> Status:
        """Its status now (asked of the server)."""
        return self.client.status(self.id, timeout_s)

    def report(self, timeout_s: float = 2.0) -> dict:
        """Its assessment so far (docs/assessment.md), as `viscera report --json`."""
        return self.client.report(self.id, timeout_s)

    def pause(self) -> Optional[Status]:
        """Stops stepping until resume() (poses are still accepted)."""
        return self.client.command(self.handle, session_request_t.kPause)

    def resume(self) -> Optional[Status]:
        """Steps again after pause()."""
        return self.client.command(self.handle, session_request_t.kResume)

    def reset(self) -> Optional[Status]:
        """Puts the intestine back in the scene's starting state."""
        return self.client.command(self.handle, session_request_t.kReset)

    def camera(self, eye: Sequence[float], target: Sequence[float],
               up: Sequence[float] = (0.0, 0.0, 1.0), fov_deg: float = 60.0) -> Optional[Status]:
        """Points the frames' laparoscope from `eye` at `target` (m), `up` its up direction,
        `fov_deg` its vertical field of view (within (1, 179) degrees)."""
        return self.client.camera(self.handle, eye, target, up, fov_deg)

    def keep_alive(self) -> None:
        """Renews the lease (poses and commands renew it too)."""
        self.client.keep_alive(self.handle)

    def destroy(self) -> Optional[Status]:
        """Stops the session; returns its last status (counts of the whole session). Once
        only: later calls return None."""
        if self._destroyed:
            return None
        self._destroyed = True
        if self.client.bus.lc is not None:
            self.client.bus.unsubscribe(self._subscription)
        return self.client.destroy(self.handle)

    def __enter__(self) -> "Session":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.destroy()

    def __repr__(self) -> str:
        return f"Session({self.id} on {self.server_id}, scene {self.handle.scene}, tools {self.tools})"


def wait_until(predicate: Callable[[], bool], pump: Callable[[float], Any], timeout_s: float) -> bool:
    """Pumps (pump(seconds)) until predicate() is true or `timeout_s` passed: the result."""
    deadline = time.monotonic() + timeout_s
    while not predicate():
        left = deadline - time.monotonic()
        if left <= 0:
            return bool(predicate())
        pump(min(0.05, left))
    return True
