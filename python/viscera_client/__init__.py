"""viscera_client: the Python client of viscerad (docs/loadtest.md).

Built on PyPI's `lcm` and the viscera_proto types lcm-gen generates from proto/.
"""
from .assessment import report_from_status
from .auth import MessageAuth
from .bus import Bus, DEFAULT_URL, make_header, resolve_url, wall_micros
from .client import Client, SessionHandle, VisceraError, session_channel
from .directory import ServerInfo, pick_server, placement_key

__all__ = ["Bus", "Client", "DEFAULT_URL", "MessageAuth", "ServerInfo", "SessionHandle",
           "VisceraError", "make_header", "pick_server", "placement_key", "report_from_status", "resolve_url",
           "session_channel", "wall_micros"]
