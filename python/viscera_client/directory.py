"""Servers heard on the heartbeat channel, and where a new session should go."""
from dataclasses import dataclass, field
from fractions import Fraction


@dataclass
class ServerInfo:
    """What the latest heartbeat of one server said (as client/server_directory.h)."""
    server_id: str
    sessions: int = 0
    max_sessions: int = 0
    load: float = 0.0       # fraction of one core
    uptime_s: float = 0.0
    heartbeats: int = 0     # heard while listening
    rejected: int = 0       # messages the server dropped since it started
    not_ours: int = 0       # messages for sessions it does not run (not in rejected)
    unconverged_solves: int = 0  # solves accepted short of tolerance, all its sessions since start
    cores: int = 0          # CPUs the server may run on (0: not announced)
    capacity: str = ""      # why it holds max_sessions (one line; "": not announced)
    limits: dict = field(default_factory=dict)  # max_rate_hz, max_session_load, ... (heartbeat)

    @property
    def has_room(self):
        return self.sessions < self.max_sessions


LIMITS = ("max_clock_skew_s", "session_lease_s", "max_message_bytes", "max_creates_per_minute",
          "max_rate_hz", "max_frame_mpix_per_s", "max_control_points", "max_obstacles",
          "max_mesh_resolution", "max_mesh_bytes", "max_settle_s", "max_session_load")


def observe(servers, heartbeat):
    """Records a heartbeat (already checked by the bus) in `servers`: id -> ServerInfo."""
    if not heartbeat.server_id:
        return
    info = servers.setdefault(heartbeat.server_id, ServerInfo(heartbeat.server_id))
    info.sessions = heartbeat.num_sessions
    info.max_sessions = heartbeat.max_sessions
    info.load = heartbeat.load
    info.uptime_s = heartbeat.uptime_us * 1e-6
    info.rejected = heartbeat.rejected
    info.not_ours = getattr(heartbeat, "not_ours", 0)
    info.unconverged_solves = getattr(heartbeat, "unconverged_solves", 0)
    info.cores = getattr(heartbeat, "cores", 0)
    info.capacity = getattr(heartbeat, "capacity", "")
    info.limits = {k: getattr(heartbeat, k) for k in LIMITS if hasattr(heartbeat, k)}
    info.heartbeats += 1


def placement_key(info):
    """Order of preference: the lower share of its capacity in use first (a big machine
    half full and a small one half full weigh alike), then the lower CPU load, then the
    id (so every client breaks ties alike). As bus::PlaceBefore (src/bus/placement.h)."""
    return (Fraction(info.sessions, info.max_sessions), info.load, info.server_id)


def pick_server(servers):
    """The server a new session should go to: the least loaded one with room, or None when
    every server is full (or none was heard). `servers`: iterable of ServerInfo."""
    candidates = [s for s in servers if s.max_sessions > 0 and s.has_room]
    return min(candidates, key=placement_key) if candidates else None
