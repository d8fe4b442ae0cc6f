"""Client-side checks of what a pose or a camera carries, with the server's limits
(server/session_manager.cc PoseProblem): a bad value fails here, at the call that made it,
with a message naming it, rather than being dropped by the server and counted as rejected."""
from __future__ import annotations

import math
from typing import Iterable, Sequence, Union

import numpy as np

#: Largest |coordinate| a pose or camera may have (m): no operating room is larger.
MAX_POSITION_M = 10.0

ToolRef = Union[int, str]


class PoseError(ValueError):
    """A pose, tool or camera value the server would refuse; the message names it."""


def tool_index(tool: ToolRef, tools: Sequence[str], session_id: int = 0) -> int:
    """The index of `tool` (a name of `tools`, or an index into it)."""
    listing = ", ".join(f"{i}: {name}" for i, name in enumerate(tools)) or "none"
    where = f"session {session_id}" if session_id else "this session"
    if isinstance(tool, (bool, np.bool_)):
        raise PoseError(f"tool must be a name or an index, got {tool!r}")
    if isinstance(tool, (int, np.integer)):
        if not 0 <= int(tool) < len(tools):
            raise PoseError(f"tool {int(tool)} does not exist: {where} has {len(tools)} "
                            f"tool(s) ({listing})")
        return int(tool)
    if isinstance(tool, str):
        if tool in tools:
            return list(tools).index(tool)
        close = [t for t in tools if t.lower() == tool.lower()]
        hint = f"; did you mean '{close[0]}'?" if close else ""
        raise PoseError(f"no tool '{tool}' in {where} (its tools: {listing}){hint}")
    raise PoseError(f"tool must be a name or an index, got {type(tool).__name__} {tool!r}")


def vector(values: Iterable[float], size: int, what: str) -> np.ndarray:
    """`values` as a float array of `size` finite numbers."""
    try:
        a = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise PoseError(f"{what} must be {size} numbers, got {values!r}") from None
    if a.shape != (size,):
        raise PoseError(f"{what} must be {size} numbers, got {a.size} "
                        f"(shape {a.shape}): {np.asarray(values).tolist()!r}")
    if not np.all(np.isfinite(a)):
        raise PoseError(f"{what} {a.tolist()} has a non-finite value")
    return a


def position(values: Iterable[float], what: str = "position") -> np.ndarray:
    """A point (x, y, z) in metres within MAX_POSITION_M of the origin on every axis."""
    p = vector(values, 3, f"{what} (x, y, z in m)")
    if np.max(np.abs(p)) > MAX_POSITION_M:
        raise PoseError(f"{what} {p.tolist()} m is beyond {MAX_POSITION_M:g} m of the scene's "
                        "origin (positions are in metres, not millimetres)")
    return p


def orientation(values: Iterable[float]) -> np.ndarray:
    """A quaternion (w, x, y, z); its norm must be within 0.5..2 (the server normalizes)."""
    q = vector(values, 4, "orientation (quaternion w, x, y, z)")
    norm = float(np.linalg.norm(q))
    if not 0.5 <= norm <= 2.0:
        raise PoseError(f"orientation {q.tolist()} has norm {norm:g}: not a rotation "
                        "(a unit quaternion w, x, y, z; identity is (1, 0, 0, 0))")
    return q


def jaw(value: float) -> float:
    """A jaw opening within [0, 1] (0 closed, 1 open)."""
    try:
        j = float(value)
    except (TypeError, ValueError):
        raise PoseError(f"jaw must be a number within [0, 1], got {value!r}") from None
    if not math.isfinite(j) or not 0.0 <= j <= 1.0:
        raise PoseError(f"jaw {j:g} must be within [0, 1] (0 closed, 1 open)")
    return j
