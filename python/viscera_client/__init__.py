"""viscera_client: the Python client of viscerad (reference: docs/python.md).

Built on PyPI's `lcm` and the viscera_proto types lcm-gen generates from proto/.

    from viscera_client import Client, Rate
    with Client() as client, client.session("cavity") as s:
        s.send_pose("right", (0.0, 0.02, 0.10), jaw=1.0)
        client.pump_for(0.5)
        print(s.latest_force("right"), s.status().state)
"""
from .assessment import report_from_status
from .auth import MessageAuth
from .bus import Bus, BusError, DEFAULT_URL, make_header, resolve_url, wall_micros
from .client import Client, SessionHandle, VisceraError, session_channel
from .directory import ServerInfo, pick_server, placement_key
from .session import Force, Rate, Session, SessionState, Status
from .validate import MAX_POSITION_M, PoseError

__all__ = ["Bus", "BusError", "Client", "DEFAULT_URL", "Force", "MAX_POSITION_M", "MessageAuth",
           "PoseError", "Rate", "ServerInfo", "Session", "SessionHandle", "SessionState",
           "Status", "VisceraError", "make_header", "pick_server", "placement_key",
           "report_from_status", "resolve_url", "session_channel", "wall_micros"]
