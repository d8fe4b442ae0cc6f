"""The load test's report: per-session and overall figures, and the health verdicts.

A run is judged twice. The client: did it keep its pose rate (a late client would make a
healthy server look slow)? The server: deadline misses within 0.1 % of steps (judged with
the run's statistical resolution, host stalls counted apart: verdict.py) and pose to force
round trip p99 within two mechanics periods (docs/capacity.md): a pose sent at a random
moment first waits up to one period for the next step to start, and that step must then
answer within its own period; frames, when asked, at 90 % of their rate or more.
"""
import statistics

from .stats import latency_summary
from .verdict import MAX_MISS_FRACTION, host_stalls, judged_misses, miss_verdict

# a status within this much after the run's end still describes the run (status at 4 Hz)
STATUS_SLACK_S = 0.125
# periods: the wait for the next step (up to one) plus the step's own budget (one)
ROUND_TRIP_LIMIT_PERIODS = 2.0
# a frame stream below this share of its asked rate is past the render capacity
MIN_FRAME_SHARE = 0.9
# a client that sends fewer than this share of its poses, or whose p99 send lateness is
# above a pose period, is too slow to judge the server by
MIN_POSE_SHARE = 0.95


def _median(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def session_report(handle, state, created, baseline, final, asked):
    """One session's figures. `state`: the worker's probe_state; status fields `created`
    (just after its creation), `baseline` (the first status heard in the run) and `final`
    (the last, sent after the last pose arrived); `asked`: the run's settings.
    Poses count from creation (no one else sends to the session), less the warm-up's;
    steps and misses from the baseline."""
    seconds = state["elapsed_s"] or 1e-9
    # the mechanics window ends with the run: statuses heard after it (the drain that waits
    # for the last poses to be counted) would add steps the run did not stream
    in_run = [(t, s) for t, s in state["statuses"] if t <= state["elapsed_s"] + STATUS_SLACK_S]
    statuses = [s for _, s in in_run]
    window_start = baseline
    window_end = statuses[-1] if statuses else final
    window_s = in_run[-1][0] - in_run[0][0] if len(in_run) >= 2 else 0.0
    steps = window_end["steps"] - window_start["steps"]
    misses = window_end["deadline_misses"] - window_start["deadline_misses"]
    # the server's own measure of its rate (over about a second), median over the run
    achieved_rate = _median([s["achieved_rate_hz"] for s in statuses])
    # poses the server counted since creation, less those of the warm-up
    accepted = final["poses"] - created["poses"] - state["poses_sent_warmup"]
    period_us = 1e6 / handle.rate_hz if handle.rate_hz > 0 else None
    lateness = latency_summary(state["send_lateness_us"])
    achieved_pose_rate = state["poses_sent"] / seconds
    client_problems = []
    if achieved_pose_rate < MIN_POSE_SHARE * asked["pose_rate_hz"]:
        client_problems.append(
            f"sent {achieved_pose_rate:.0f} of {asked['pose_rate_hz']:g} poses/s "
            f"({state['ticks_skipped']} ticks skipped): this client is too slow or too busy")
    if lateness["p99"] is not None and lateness["p99"] > 1e6 / asked["pose_rate_hz"]:
        client_problems.append(f"p99 pose send lateness {lateness['p99']:.0f} us is above the "
                               f"pose period: this client wakes up late")
    rt = latency_summary(state["round_trips_us"])
    limit_us = ROUND_TRIP_LIMIT_PERIODS * period_us if period_us else None
    report = {
        "session_id": handle.session_id,
        "server": handle.server_id,
        "scene": handle.scene,
        "tools": handle.tools,
        "rate_hz": handle.rate_hz,
        "round_trip_limit_us": limit_us,
        "seconds": state["elapsed_s"],
        "poses": {
            "sent": state["poses_sent"],
            "rate_hz": achieved_pose_rate,
            "accepted": accepted,
            # sent but never counted by the server (lost on the way or rejected)
            "lost": max(0, state["poses_sent"] - accepted),
            "answered": state["poses_answered"],
            "ticks_skipped": state["ticks_skipped"],
            "send_lateness_us": lateness,
        },
        "forces": {"received": state["forces_received"], "lost": state["forces_lost"]},
        "round_trip_us": rt,
        "mechanics": {
            "window_s": window_s,
            "steps": steps,
            "achieved_rate_hz": achieved_rate if achieved_rate is not None else steps / seconds,
            "deadline_misses": misses,
            "miss_fraction": misses / steps if steps > 0 else None,
            "step_cost_p50_us": _median([s["step_cost_p50_us"] for s in statuses]),
            "step_cost_p99_us": max([s["step_cost_p99_us"] for s in statuses], default=None),
            "jitter_p99_us": max([s["jitter_p99_us"] for s in statuses], default=None),
            "rejected": final["rejected"] - baseline["rejected"],
        },
        "frames": None,
        "client": {"ok": not client_problems, "problems": client_problems},
        "timeline": state["timeline"],
        "status_timeline": [dict(t=t, achieved_rate_hz=s["achieved_rate_hz"],
                                 deadline_misses=s["deadline_misses"] - baseline["deadline_misses"],
                                 step_cost_p99_us=s["step_cost_p99_us"])
                            for t, s in in_run],
    }
    if asked["frames"]:
        report["frames"] = {
            "received": state["frames_received"],
            "lost": state["frames_lost"],
            "rate_hz": state["frames_received"] / seconds,
            "asked_rate_hz": handle.frame_rate_hz or asked["frame_rate_hz"],
            "skipped_by_server": final["frames_dropped"] - baseline["frames_dropped"],
            "age_ms": latency_summary(state["frame_ages_ms"]),
            "delivery_ms": latency_summary(state["frame_delays_ms"]),
            "render_ms_p50": _median([s["render_ms"] for s in statuses]),
            "skin_ms_p50": _median([s["skin_ms"] for s in statuses]),
            "encode_ms_p50": _median([s["encode_ms"] for s in statuses]),
        }
    report["server_problems"] = server_problems(report)
    report["server_ok"] = not report["server_problems"]
    return report


def server_problems(s):
    """Why a session's figures (a session_report) are past the server's capacity, or []:
    deadline misses resolved above 0.1 % of steps (miss_verdict), round-trip p99 above two
    periods, no pose answered, or, with frames, a stream below 90 % of its asked rate (the
    renderer skipping ticks)."""
    problems = []
    m, rt = s["mechanics"], s["round_trip_us"]
    m["miss_verdict"] = miss_verdict(m["deadline_misses"], m["steps"])
    if m["miss_verdict"]["verdict"] == "over":
        problems.append(m["miss_verdict"]["text"])
    limit_us = s["round_trip_limit_us"]
    if limit_us and rt["p99"] is not None and rt["p99"] > limit_us:
        problems.append(f"round-trip p99 {rt['p99']:.0f} us > {ROUND_TRIP_LIMIT_PERIODS:g} "
                        f"periods ({limit_us:.0f} us)")
    if rt["count"] == 0:
        problems.append("no pose was answered by a force")
    f = s["frames"]
    if f is not None and f["asked_rate_hz"] and f["rate_hz"] < MIN_FRAME_SHARE * f["asked_rate_hz"]:
        problems.append(f"frames at {f['rate_hz']:.1f} of {f['asked_rate_hz']:g} Hz "
                        f"({f['skipped_by_server']} ticks skipped by the renderer)")
    return problems


def run_problems(overall, sessions):
    """Why a whole run is past the server's capacity, or []: the same limits as
    server_problems over the figures of every session pooled (deadline misses over all
    steps, the pooled round-trip p99 against the longest limit), and the slowest frame stream.
    Pooled, because a short run of one session has too few steps to judge 0.1 % on its own;
    the misses of host stalls left out while stalls stay rare (verdict.judged_misses)."""
    problems = []
    if overall["miss_verdict"]["verdict"] == "over":
        problems.append(overall["miss_verdict"]["text"])
    limits = [s["round_trip_limit_us"] for s in sessions if s["round_trip_limit_us"]]
    p99 = overall["round_trip_us"]["p99"]
    if limits and p99 is not None and p99 > max(limits):
        problems.append(f"pooled round-trip p99 {p99:.0f} us > {max(limits):.0f} us")
    if overall["round_trip_us"]["count"] == 0:
        problems.append("no pose was answered by a force")
    for s in sessions:
        f = s["frames"]
        if f is not None and f["asked_rate_hz"] and \
                f["rate_hz"] < MIN_FRAME_SHARE * f["asked_rate_hz"]:
            problems.append(f"a frame stream at {f['rate_hz']:.1f} of {f['asked_rate_hz']:g} Hz")
            break
    return problems


def overall_report(sessions, pooled_round_trips_us, asked, drops, interrupted, started_utc):
    """The run as a whole: round trips of every session pooled, sums of counts, verdicts."""
    servers = {}
    for s in sessions:
        servers[s["server"]] = servers.get(s["server"], 0) + 1
    total = lambda f: sum(f(s) for s in sessions)  # noqa: E731
    steps = total(lambda s: s["mechanics"]["steps"])
    misses = total(lambda s: s["mechanics"]["deadline_misses"])
    out = {
        "started_utc": started_utc,
        "interrupted": interrupted,
        "sessions": len(sessions),
        "servers": servers,
        "settings": asked,
        "poses_sent": total(lambda s: s["poses"]["sent"]),
        "poses_accepted": total(lambda s: s["poses"]["accepted"]),
        "poses_lost": total(lambda s: s["poses"]["lost"]),
        "forces_received": total(lambda s: s["forces"]["received"]),
        "forces_lost": total(lambda s: s["forces"]["lost"]),
        "pose_rate_hz_min": min((s["poses"]["rate_hz"] for s in sessions), default=None),
        "mechanics_rate_hz_min": min((s["mechanics"]["achieved_rate_hz"] for s in sessions),
                                     default=None),
        "round_trip_us": latency_summary(pooled_round_trips_us),
        "steps": steps,
        "deadline_misses": misses,
        "miss_fraction": misses / steps if steps > 0 else None,
        "step_cost_p50_us": _median([s["mechanics"]["step_cost_p50_us"] for s in sessions]),
        "step_cost_p99_us": max((s["mechanics"]["step_cost_p99_us"] for s in sessions
                                 if s["mechanics"]["step_cost_p99_us"] is not None), default=None),
        "frames": None,
        "dropped_by_client_bus": drops,
        "client_ok": all(s["client"]["ok"] for s in sessions),
    }
    run_seconds = max((s["seconds"] for s in sessions), default=0.0)
    stalls = host_stalls(sessions)
    judged, excluded = judged_misses(misses, stalls, run_seconds)
    out["host_stalls"] = {"seconds": stalls["seconds"], "misses": stalls["misses"],
                          "left_out_of_verdict": excluded,
                          "sessions_hit": {str(t): len(hit) for t, hit in stalls["by_second"].items()}}
    out["miss_verdict"] = miss_verdict(judged, steps)
    out["miss_verdict"]["judged_misses"] = judged
    if asked["frames"]:
        out["frames"] = {
            "received": total(lambda s: s["frames"]["received"]),
            "lost": total(lambda s: s["frames"]["lost"]),
            "rate_hz_min": min(s["frames"]["rate_hz"] for s in sessions),
            "skipped_by_server": total(lambda s: s["frames"]["skipped_by_server"]),
        }
    if excluded:
        # a session's own verdict leaves out its misses of the run's stall seconds too
        for s in sessions:
            own = sum(hit.get(s["session_id"], 0) for hit in stalls["by_second"].values())
            if own:
                m = s["mechanics"]
                m["miss_verdict"] = miss_verdict(max(0, m["deadline_misses"] - own), m["steps"])
                m["miss_verdict"]["host_stall_misses"] = own
                s["server_problems"] = [p for p in s["server_problems"] if "deadline miss" not in p]
                if m["miss_verdict"]["verdict"] == "over":
                    s["server_problems"].insert(0, m["miss_verdict"]["text"])
                s["server_ok"] = not s["server_problems"]
    out["server_problems"] = run_problems(out, sessions)
    out["server_ok"] = not out["server_problems"]
    out["server_verdict"] = ("over capacity" if not out["server_ok"] else
                             "unresolved" if out["miss_verdict"]["verdict"] == "unresolved" else "ok")
    return out


def text_summary(report):
    """A few lines for the terminal."""
    o = report["overall"]
    a = o["settings"]
    rt = o["round_trip_us"]
    fmt = lambda v, f="{:.0f}": "-" if v is None else f.format(v)  # noqa: E731
    lines = [
        f"{o['sessions']} sessions on {len(o['servers'])} server(s) "
        f"({', '.join(f'{k}: {v}' for k, v in sorted(o['servers'].items()))}), "
        f"{a['seconds']:g} s, poses at {a['pose_rate_hz']:g} Hz, scene {a['scene']}"
        + (", frames" if a["frames"] else ""),
        f"round trip pose->force  p50 {fmt(rt['p50'])}  p95 {fmt(rt['p95'])}  "
        f"p99 {fmt(rt['p99'])}  max {fmt(rt['max'])} us  ({rt['count']} poses answered)",
        f"poses sent {o['poses_sent']}, lost {o['poses_lost']}; forces received "
        f"{o['forces_received']}, lost {o['forces_lost']}",
        f"mechanics  {plural(o['deadline_misses'], 'deadline miss', 'deadline misses')} in "
        f"{o['steps']} steps "
        f"({fmt(None if o['miss_fraction'] is None else 100 * o['miss_fraction'], '{:.3f}')} %), "
        f"step cost p50 {fmt(o['step_cost_p50_us'])} us, p99 {fmt(o['step_cost_p99_us'])} us",
    ]
    stalls = o["host_stalls"]
    if stalls["seconds"]:
        lines.append(
            f"host stall {plural(stalls['misses'], 'miss', 'misses')} hit most sessions at once in "
            f"second(s) {', '.join(str(t) for t in stalls['seconds'])} of the run: the machine "
            "paused every thread, not a server short of cores"
            + ("; left out of the verdict" if stalls["left_out_of_verdict"] else
               "; too many to leave out: the machine itself is overloaded"))
    lines.append(f"resolution {o['miss_verdict']['text']}")
    if o["frames"]:
        f = o["frames"]
        lines.append(f"frames     {f['received']} received, {f['lost']} lost, slowest stream "
                     f"{f['rate_hz_min']:.1f} Hz, {f['skipped_by_server']} skipped by the renderers")
    for s in report["sessions"]:
        for p in s["client"]["problems"]:
            lines.append(f"CLIENT     session {s['session_id']}: {p}")
        for p in s["server_problems"]:
            lines.append(f"session    {s['session_id']} on {s['server']}: {p}")
    for p in o["server_problems"]:
        lines.append(f"SERVER     {p}")
    server = {"ok": "ok", "over capacity": "OVER CAPACITY",
              "unresolved": "ok as far as this run can tell (see resolution)"}[o["server_verdict"]]
    lines.append("verdict    client " + ("ok" if o["client_ok"] else "TOO SLOW (figures unreliable)")
                 + ", server " + server)
    return "\n".join(lines)


def plural(n, one, many):
    """ "1 deadline miss", "2 deadline misses"."""
    return f"{n} {one if n == 1 else many}"
