"""A load-test worker process: streams poses to its sessions at a fixed rate and measures
what comes back (forces, status, frames). One LCM object and one thread per process;
tools/loadtest.py spreads the sessions over a few processes (--processes), so Python's GIL
never paces all of them.
"""
import math
import signal
import time

import viscera_proto

from ..auth import MessageAuth
from ..bus import Bus, PROTOCOL_VERSION, make_header
from ..client import session_channel
from ..fast import force_echo, frame_times
from .stats import SessionProbe

# A frame stream of 25 Hz needs more than the kernel's default socket buffer (as
# client/frame_receiver.h): a second of frames fits in 2 MB.
FRAME_RECV_BUF = 2 * 1024 * 1024


def with_recv_buf(url, size):
    if not url.startswith("udpm://") or "recv_buf_size=" in url:
        return url
    return f"{url}{'&' if '?' in url else '?'}recv_buf_size={size}"


class PoseStream:
    """Tool poses of one session: a slow 1 cm circle around `center` (so every pose
    differs and the tool moves), jaws open."""

    def __init__(self, bus, handle, tool, center):
        self.bus = bus
        self.channel = session_channel("POSE", handle.session_id)
        self.msg = viscera_proto.tool_pose_t()
        self.msg.tool = tool
        self.msg.orientation = [1.0, 0.0, 0.0, 0.0]
        self.msg.jaw = 1.0
        self.handle = handle
        self.center = center

    def send(self, t):
        self.msg.header = make_header(self.handle.session_id, 0, self.handle.token)
        self.bus.stamp(self.msg, self.channel)
        a = 2.0 * math.pi * 0.5 * t
        c = self.center
        self.msg.position = [c[0] + 0.01 * math.cos(a), c[1] + 0.01 * math.sin(a), c[2]]
        self.bus.publish(self.channel, self.msg)


def run_worker(index, url, key, handles, slots, tool, pose_rate_hz, warmup, seconds, frames,
               center, go, start_wall, stop, progress, results):
    """Process entry of worker `index`: subscribes, says ("ready", index) on `results`,
    waits for `go`, then streams to `handles` from `warmup` seconds before wall time
    `start_wall.value` (not measured) until `seconds` after it (or until `stop` is set) and
    puts ("done", index, {session_id: probe state})
    on `results` (or ("error", index, text)). `progress`: a shared array, 2 entries per
    session (poses sent, forces received) at 2 * slots[i] for handles[i]. SIGINT is left to
    the parent, which stops us cleanly."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        _run(index, url, key, handles, slots, tool, pose_rate_hz, warmup, seconds, frames,
             center, go, start_wall, stop, progress, results)
    except Exception:  # the parent reports it; the other workers go on
        import traceback
        results.put(("error", index, traceback.format_exc()))


def _run(index, url, key, handles, slots, tool, pose_rate_hz, warmup, seconds, frames,
         center, go, start_wall, stop, progress, results):
    auth = MessageAuth(key) if key else None
    bus = Bus(with_recv_buf(url, FRAME_RECV_BUF) if frames else url, auth)
    period = 1.0 / pose_rate_hz
    probes, streams = [], []
    for i, h in enumerate(handles):
        probe = SessionProbe(h, tool, period, 0.0)
        probes.append(probe)
        streams.append(PoseStream(bus, h, tool, center))
        slot = 2 * slots[i]

        def on_force(data, chan, recv_utime, probe=probe, slot=slot):
            echo = force_echo(data)
            if echo is None or echo[0] != PROTOCOL_VERSION:
                bus.drops["malformed"] += 1
                return
            probe.on_force(echo[1], echo[2], echo[3], echo[4], recv_utime, time.monotonic())
            progress[slot + 1] += 1

        def on_frame(data, chan, recv_utime, probe=probe):
            t = frame_times(data)
            if t is None or t[0] != PROTOCOL_VERSION:
                bus.drops["malformed"] += 1
                return
            probe.on_frame(t[1], t[2], t[3], recv_utime)

        bus.subscribe_raw(session_channel("FORCE", h.session_id), on_force)
        bus.subscribe(session_channel("STATUS", h.session_id), viscera_proto.session_status_t,
                      lambda s, chan, t, probe=probe: probe.on_status(s, time.monotonic()))
        if frames:
            bus.subscribe_raw(session_channel("FRAME", h.session_id), on_frame)

    results.put(("ready", index, None))
    while not go.is_set() and not stop.is_set():
        bus.pump(0.02)
    # the same instant for every worker: wall clock to monotonic once, here
    start = time.monotonic() + (start_wall.value - time.time())
    first_pose = start - warmup
    for i, p in enumerate(probes):
        p.start = first_pose
        # stagger sessions over one period: poses of N sessions do not leave in one burst
        p.next_pose = first_pose + period * (slots[i] % 16) / 16.0
    end = start + seconds
    streamed_end = start
    measuring = False
    # until the first pose, only listen
    while time.monotonic() < first_pose and not stop.is_set():
        bus.pump(min(0.05, max(0.0, first_pose - time.monotonic())))
    while not stop.is_set():
        now = time.monotonic()
        if now >= end:
            break
        if not measuring and now >= start:
            # the warm-up is over (first contacts, caches, the renderer's first frames): what
            # was measured so far is not the run's
            measuring = True
            for p in probes:
                p.begin_measurement(start)
        streamed_end = now
        for k, (probe, stream) in enumerate(zip(probes, streams)):
            if probe.next_pose > now:
                continue
            behind = int((now - probe.next_pose) / period)
            if behind > 0:  # this client fell behind: skip the ticks, never send a burst
                probe.ticks_skipped += behind
                probe.next_pose += behind * period
            stream.send(now - first_pose)
            probe.on_pose_sent(probe.next_pose, time.monotonic())
            progress[2 * slots[k]] += 1
            probe.next_pose += period
        wake = min(p.next_pose for p in probes)
        bus.pump(max(0.0, wake - time.monotonic()), max_messages=64)
    # The last answers, and a status of each session that counts every pose sent (a busy
    # server's I/O thread may count the last ones after a status or two): statuses come at
    # 4 Hz, so wait up to 2 s; a pose really lost keeps us waiting that long.
    stopped = time.monotonic()
    drain_end = stopped + 2.0
    settled = stopped + 0.3

    def counted(p):
        return p.statuses and p.statuses[-1][1]["poses"] >= p.poses_sent + p.poses_sent_warmup

    while time.monotonic() < drain_end:
        bus.pump(min(0.05, drain_end - time.monotonic()))
        if time.monotonic() > settled and all(counted(p) for p in probes):
            break
    out = {}
    for p in probes:
        out[p.handle.session_id] = probe_state(p, max(0.0, streamed_end - start))
    out["_drops"] = dict(bus.drops)
    results.put(("done", index, out))


def probe_state(p, elapsed_s):
    """What the parent needs of a probe (picklable, no handle objects)."""
    return {
        "elapsed_s": elapsed_s,
        "poses_sent": p.poses_sent,
        "poses_sent_warmup": p.poses_sent_warmup,
        "ticks_skipped": p.ticks_skipped,
        "send_lateness_us": p.send_lateness_us,
        "round_trips_us": p.round_trips_us,
        "poses_answered": p.poses_answered,
        "forces_received": p.forces.received,
        "forces_lost": p.forces.lost,
        "frames_received": p.frames.received,
        "frames_lost": p.frames.lost,
        "frame_ages_ms": p.frame_ages_ms,
        "frame_delays_ms": p.frame_delays_ms,
        "statuses": p.statuses,
        "timeline": p.timeline(elapsed_s),
    }
