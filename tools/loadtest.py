#!/usr/bin/env python3
"""Load test of viscerad: N sessions spread over every server heard, poses streamed to each
at a fixed rate from worker processes, forces, status and frames measured.

  tools/loadtest.py --sessions 4 --seconds 10 --pose-rate 100 --scene cavity \
      --json report.json --plots plots/
  tools/loadtest.py --sessions 1,2,4,8 ...     several runs, one after the other, and a
                                               capacity curve with --plots

Stops by itself after --seconds (and on Ctrl-C), destroying every session it created.
docs/capacity.md explains the figures; the JSON report is an object {"overall": {...},
"sessions": [{"server": ..., ...}, ...]} (with several runs: {"runs": [report, ...]}).
Exit status: 0 when the server kept up (or this run cannot resolve the 0.1 % miss limit
either way: the verdict says so) and the client kept its rate, 1 when the server did not
(over capacity), 2 on errors, 3 when this client could not keep its own pose rate, 4 when
a server refused for a reason that every session would meet again (an unknown scene, a bad
scene file, a rate above the server's limit, a key that does not match the servers').
"""
import argparse
import datetime
import json
import multiprocessing
import os
import platform
import queue
import re
import signal
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _import_client():
    """viscera_client from the environment (pip install ./python), else from this checkout
    (python/ and the build tree's lcm-gen output); re-runs itself under the checkout's
    virtual environment (tools/setup.sh makes it) when this Python has no `lcm`."""
    try:
        import lcm  # noqa: F401
    except ImportError:
        venv_python = os.path.join(os.environ.get("VISCERA_VENV", os.path.join(ROOT, ".venv")),
                                   "bin", "python")
        if os.path.exists(venv_python) and os.path.realpath(sys.executable) != \
                os.path.realpath(venv_python):
            os.execv(venv_python, [venv_python] + sys.argv)
        sys.exit("loadtest: Python module 'lcm' missing: run tools/setup.sh (it makes .venv)")
    try:
        import viscera_proto  # noqa: F401
    except ImportError:
        build = os.environ.get("VISCERA_BUILD_DIR", os.path.join(ROOT, "build"))
        sys.path.insert(0, os.path.join(build, "python"))
        os.environ["PYTHONPATH"] = os.pathsep.join(
            [os.path.join(build, "python"), os.environ.get("PYTHONPATH", "")])
    try:
        import viscera_client  # noqa: F401
    except ImportError:
        sys.path.insert(0, os.path.join(ROOT, "python"))
        os.environ["PYTHONPATH"] = os.pathsep.join(
            [os.path.join(ROOT, "python"), os.environ.get("PYTHONPATH", "")])
    try:
        import viscera_proto  # noqa: F401,F811
    except ImportError:
        sys.exit("loadtest: viscera_proto not found: build the project (cmake) or "
                 "pip install ./python")


_import_client()

from viscera_client import Client, VisceraError, pick_server  # noqa: E402
from viscera_client.load import report as rep  # noqa: E402
from viscera_client.load.stats import status_fields  # noqa: E402
from viscera_client.load.worker import run_worker  # noqa: E402
from viscera_proto import session_reply_t  # noqa: E402


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sessions", required=True,
                   help="sessions per run (N), or several runs N1,N2,... for a capacity curve")
    p.add_argument("--seconds", type=float, required=True, help="streaming time of each run (s)")
    p.add_argument("--pose-rate", type=float, required=True, help="poses per second per session")
    p.add_argument("--warmup", type=float, default=1.0,
                   help="seconds of poses before measuring (first contacts, caches, first "
                        "frames; default 1)")
    p.add_argument("--scene", help="scene name in the servers' scene directory (default: cavity)")
    p.add_argument("--scene-file", action="append", default=[],
                   help="send this scene inline (repeat: files joined in order, e.g. a scene "
                        "and a [[tool]] fragment)")
    p.add_argument("--session-rate", type=float, default=0.0,
                   help="mechanics rate of each session (Hz; default: the scene's)")
    p.add_argument("--frames", action="store_true", help="ask for frames and measure them")
    p.add_argument("--frame-rate", type=float, default=25.0, help="with --frames (Hz)")
    p.add_argument("--skeleton-rate", type=float, default=-1.0,
                   help="skeleton states per second each session publishes, as for a page that "
                        "draws the session itself (Hz; default: none)")
    p.add_argument("--key-file", help="pre-shared key file (sign and check MACs)")
    p.add_argument("--json", metavar="REPORT.json", help="write the report here")
    p.add_argument("--plots", metavar="DIR", help="write PNG plots here (matplotlib)")
    p.add_argument("--lcm-url", help="LCM URL (default: $LCM_DEFAULT_URL, else LCM's usual "
                                     "group with ttl=0)")
    p.add_argument("--server", help="put every session on this server (default: spread them "
                                    "over every server heard, least loaded first)")
    p.add_argument("--tool", type=int, default=0, help="tool index driven (default 0)")
    p.add_argument("--center", type=float, nargs=3, default=[0.0, 0.0, 0.15],
                   metavar=("X", "Y", "Z"), help="centre of the tool's 1 cm circle (m)")
    p.add_argument("--processes", type=int, default=0,
                   help="worker processes streaming the sessions (default: one per session, "
                        "at most twice the CPUs this process may use)")
    p.add_argument("--listen", type=float, default=1.2,
                   help="seconds to listen for server heartbeats before placing sessions")
    p.add_argument("--progress", choices=["auto", "bar", "lines", "none"], default="auto",
                   help="progress display (auto: a bar on a terminal, else a line per 5 s)")
    a = p.parse_args(argv)
    try:
        a.runs = [int(x) for x in a.sessions.split(",")]
    except ValueError:
        p.error(f"--sessions {a.sessions}: expected N or N1,N2,...")
    if any(n < 1 for n in a.runs):
        p.error("--sessions: every run needs at least 1 session")
    if a.seconds <= 0 or a.pose_rate <= 0 or a.warmup < 0:
        p.error("--seconds and --pose-rate must be > 0, --warmup >= 0")
    if a.scene and a.scene_file:
        p.error("--scene and --scene-file exclude each other")
    if not a.scene and not a.scene_file:
        a.scene = "cavity"
    return a


class Progress:
    """A progress bar on a terminal (stderr), else a line every 5 s."""

    def __init__(self, mode, seconds, label):
        self.bar = mode == "bar" or (mode == "auto" and sys.stderr.isatty())
        self.quiet = mode == "none"
        self.seconds, self.label = seconds, label
        self.last_line = 0.0

    def show(self, elapsed, poses, forces, final=False):
        if self.quiet:
            return
        frac = min(1.0, max(0.0, elapsed / self.seconds))
        clock = "warm-up" if elapsed < 0 else f"{min(elapsed, self.seconds):5.1f}/{self.seconds:g} s"
        text = f"{self.label} {clock}  poses {poses}  forces {forces}"
        if self.bar:
            width = 30
            filled = int(frac * width)
            sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {text}  ")
            if final:
                sys.stderr.write("\n")
            sys.stderr.flush()
        elif final or elapsed - self.last_line >= 5.0:
            self.last_line = elapsed
            print(f"loadtest: {text}", file=sys.stderr, flush=True)


def is_capacity_refusal(error):
    """True when a VisceraError is a server saying it has no room now (full, or no core
    budget left for this session): another server, or later, may take it. Any other
    refusal (a bad scene, a rate above the limit) would come again."""
    text = str(error)
    return error.result == session_reply_t.kRefused and (
        " is full (" in text or "has no room for this session" in text
        or "too many creates" in text or "frame bandwidth" in text)


class Refused(Exception):
    """A refusal that every further session would meet again: stop, exit status 4."""


# how long to wait for servers that are still measuring their capacity (viscerad takes a
# second or two after start, longer on a busy machine)
MEASURING_WAIT_S = 60.0
# for the first heartbeat: a viscerad started just before (README's two commands) took more
# than 10 s to send its first on this 2-core machine at load average 15
FIRST_SERVER_WAIT_S = 30.0
# between the runs of --sessions N1,N2,...
RUN_PAUSE_S = 2.0


def hear_servers(client, args, log):
    """The servers heard (ServerInfo list). Servers still measuring their capacity (their
    heartbeat says so) are waited for, up to MEASURING_WAIT_S, so that a load test started
    right after viscerad sees the capacity it will have. A key that does not match the
    servers' is a Refused: every heartbeat fails its MAC."""
    servers = client.servers(args.listen, timeout_s=FIRST_SERVER_WAIT_S)
    deadline = time.monotonic() + MEASURING_WAIT_S
    said = False
    while servers and any("until" in s.capacity for s in servers) and time.monotonic() < deadline:
        if not said:
            log("waiting for " + ", ".join(s.server_id for s in servers if "until" in s.capacity)
                + f" to measure its capacity (up to {MEASURING_WAIT_S:g} s)")
            said = True
        servers = client.servers(1.2)
    if not servers and client.bus.drops["malformed"] > 0:
        raise Refused(f"{client.bus.drops['malformed']} heartbeat(s) heard that this client cannot "
                      "decode: its viscera_proto types differ from the servers' (an older build: "
                      "re-run tools/setup.sh, or put the build's python/ first on PYTHONPATH)")
    if not servers and client.bus.drops["bad_mac"] > 0:
        raise Refused(f"{client.bus.drops['bad_mac']} heartbeat(s) heard with a MAC that does not "
                      "match --key-file: the servers use another key (or none)")
    if not servers and client.bus.auth is None:
        log("no server heard: if the servers were started with --key-file, give the same key")
    return servers


def create_sessions(client, args, n, scene_toml, log, servers):
    """N sessions, each on the least loaded server with room (or on --server), among
    `servers` (heard once); each placement then counts itself, since the next heartbeat
    would come too late to see it. A refusal that is not about room (a bad scene, a rate
    above the server's limit) stops everything: Refused."""
    if not args.server:
        if not servers:
            raise VisceraError(f"no server heard on {client.bus.url} within {FIRST_SERVER_WAIT_S:g} s "
                               "(is viscerad running? a multicast route?)")
        log("servers: " + ", ".join(f"{s.server_id} {s.sessions}/{s.max_sessions} "
                                    f"load {s.load:.2f}" for s in servers))
    created = []
    try:
        while len(created) < n:
            if args.server:
                target = args.server
            else:
                chosen = pick_server(servers)
                if chosen is None:
                    raise VisceraError(
                        f"every server is full after {len(created)} of {n} sessions ("
                        + "; ".join(f"{s.server_id}: {s.capacity or f'max {s.max_sessions}'}"
                                    for s in servers) + ")")
                target = chosen.server_id
            try:
                h = client.create(scene=args.scene, scene_toml=scene_toml, server=target,
                                  rate_hz=args.session_rate,
                                  frame_rate_hz=args.frame_rate if args.frames else -1.0,
                                  skeleton_rate_hz=args.skeleton_rate, timeout_s=10.0)
            except ValueError as e:  # refused by the client's own checks (a rate out of range)
                raise Refused(f"{e} (every session would be refused alike: stopping)")
            except VisceraError as e:
                if e.result is not None and not is_capacity_refusal(e):
                    # the server knows an inline scene as "<scene dir>/<inline>": name the files
                    why = re.sub(r"\S*<inline>", " + ".join(args.scene_file) or "<inline>", str(e))
                    raise Refused(f"{why} (every session would be refused alike: stopping)")
                if args.server or e.result is None:
                    raise
                log(f"{e}; trying another server")
                chosen.sessions = chosen.max_sessions  # full, or refusing: place elsewhere
                continue
            if not args.server:
                chosen.sessions += 1
            create_status = client.status(h.session_id)
            created.append((h, status_fields(create_status)))
            log(f"session {h.session_id} on server {h.server_id} ({h.scene}, {h.rate_hz:g} Hz, "
                f"tools {', '.join(h.tools) or 'none'})")
    except BaseException:
        destroy_all(client, [h for h, _ in created], log)
        raise
    return created


def destroy_all(client, handles, log):
    for h in handles:
        try:
            client.destroy(h)
        except VisceraError as e:
            log(f"could not destroy session {h.session_id}: {e}")


def run_once(args, n, scene_toml, log):
    """One run of n sessions: (report dict, {session_id: round trips in us})."""
    started_utc = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    client = Client(args.lcm_url, args.key_file)
    load_before = os.getloadavg()
    servers = hear_servers(client, args, log)
    created = create_sessions(client, args, n, scene_toml, log, servers)
    handles = [h for h, _ in created]
    if handles and args.tool >= len(handles[0].tools):
        destroy_all(client, handles, log)
        raise VisceraError(f"tool {args.tool} does not exist: the scene has tools "
                           f"{handles[0].tools or 'none'} (use a scene with a [[tool]])")
    ctx = multiprocessing.get_context("spawn")
    go, stop = ctx.Event(), ctx.Event()
    start_wall = ctx.Value("d", 0.0)
    progress = ctx.Array("q", 2 * n, lock=False)
    results = ctx.Queue()
    key = client.bus.auth._key if client.bus.auth else None
    # session i goes to process i mod P
    processes = min(n, args.processes or 2 * len(os.sched_getaffinity(0)))
    workers = [ctx.Process(target=run_worker, daemon=True,
                           args=(w, client.bus.url, key, handles[w::processes],
                                 list(range(n))[w::processes], args.tool, args.pose_rate,
                                 args.warmup, args.seconds, args.frames, args.center, go,
                                 start_wall, stop, progress, results))
               for w in range(processes)]
    states, errors, drops = {}, [], {}
    interrupted = []

    def on_sigint(signum, frame):
        # Ctrl-C: stop streaming, keep collecting, destroy the sessions, report what we have
        if not interrupted:
            log("interrupted: stopping the workers, destroying the sessions")
        interrupted.append(True)
        stop.set()

    previous_handler = signal.signal(signal.SIGINT, on_sigint)
    try:
        for w in workers:
            w.start()
        ready = 0
        deadline = time.monotonic() + 60.0
        while ready + len(errors) < processes and time.monotonic() < deadline and \
                not stop.is_set():
            try:
                kind, index, payload = results.get(timeout=0.2)
            except queue.Empty:
                continue
            if kind == "ready":
                ready += 1
            elif kind == "error":
                errors.append(payload)
            elif not any(w.is_alive() for w in workers):
                break  # they died without a word (e.g. killed): nothing more will come
        if not stop.is_set() and (errors or ready < processes):
            raise VisceraError(f"{processes - ready} worker(s) did not start: "
                               f"{''.join(errors)[-2000:]}")
        # every worker then knows when to begin: poses at once, measurements after the warm-up
        start_wall.value = time.time() + 0.3 + args.warmup
        go.set()
        bar = Progress(args.progress, args.seconds, f"{n} sessions")
        done = 0
        while done < processes:
            try:
                kind, index, payload = results.get(timeout=0.2)
            except queue.Empty:
                kind = None
            if kind == "done":
                done += 1
                for k, v in payload.items():
                    if k == "_drops":
                        for d, c in v.items():
                            drops[d] = drops.get(d, 0) + c
                    else:
                        states[k] = v
            elif kind == "error":
                done += 1
                errors.append(payload)
            elif kind is None and (not any(w.is_alive() for w in workers) or
                                   time.time() > start_wall.value + args.seconds + 30.0):
                log(f"{processes - done} worker(s) never reported")
                break
            bar.show(time.time() - start_wall.value, sum(progress[0::2]), sum(progress[1::2]),
                     final=done == processes)
    finally:
        stop.set()
        for w in workers:
            w.join(timeout=5.0)
            if w.is_alive():
                w.terminate()
        destroy_all(client, handles, log)
        signal.signal(signal.SIGINT, previous_handler)
    interrupted = bool(interrupted)
    if errors:
        raise VisceraError("worker failed:\n" + "\n".join(errors)[-3000:])
    asked = {"sessions": n, "seconds": args.seconds, "warmup_s": args.warmup,
             "pose_rate_hz": args.pose_rate,
             "session_rate_hz": args.session_rate, "scene": args.scene or "+".join(
                 os.path.basename(f) for f in args.scene_file),
             "frames": args.frames, "frame_rate_hz": args.frame_rate if args.frames else 0.0,
             "tool": args.tool, "lcm_url": client.bus.url, "signed": bool(args.key_file)}
    sessions, round_trips = [], {}
    for h, create_status in created:
        state = states.get(h.session_id)
        if state is None:
            continue
        statuses = [s for _, s in state["statuses"]]
        baseline = statuses[0] if statuses else create_status
        final = statuses[-1] if statuses else create_status
        s = rep.session_report(h, state, create_status, baseline, final, asked)
        sessions.append(s)
        round_trips[h.session_id] = state["round_trips_us"]
    pooled = [x for v in round_trips.values() for x in v]
    overall = rep.overall_report(sessions, pooled, asked, drops, interrupted, started_utc)
    overall["context"] = run_context(servers, load_before)
    return {"overall": overall, "sessions": sessions}, round_trips


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def source_commit():
    """The checkout's commit (with "-dirty" when it has changes), or None outside git."""
    try:
        commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "HEAD"], capture_output=True,
                                text=True, timeout=5).stdout.strip()
        dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=5).stdout.strip()
        return (commit + ("-dirty" if dirty else "")) or None
    except (OSError, subprocess.SubprocessError):
        return None


def run_context(servers, load_before):
    """What a planner needs to read the figures: this machine (cores, CPU, load average
    before and after the run), the servers heard (their capacity and limits), the commit."""
    return {
        "machine": {"host": platform.node(), "cpus": os.cpu_count(),
                    "cpus_usable": len(os.sched_getaffinity(0)), "cpu_model": cpu_model(),
                    "loadavg_before": list(load_before), "loadavg_after": list(os.getloadavg()),
                    "python": platform.python_version()},
        "servers": [{"server_id": s.server_id, "sessions_before": s.sessions,
                     "max_sessions": s.max_sessions, "cores": s.cores, "capacity": s.capacity,
                     "load": s.load, "uptime_s": s.uptime_s, "limits": s.limits}
                    for s in servers],
        "commit": source_commit(),
    }


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    log = lambda m: print(f"loadtest: {m}", file=sys.stderr, flush=True)  # noqa: E731
    scene_toml = None
    if args.scene_file:
        try:
            scene_toml = "\n".join(open(f).read() for f in args.scene_file)
        except OSError as e:
            log(f"cannot read scene file: {e}")
            return 2
    reports, round_trips = [], {}
    try:
        for i, n in enumerate(args.runs):
            if i > 0:
                # the previous run's sessions end their threads and records: the next run does
                # not start on a machine still busy with them
                time.sleep(RUN_PAUSE_S)
            r, rt = run_once(args, n, scene_toml, log)
            reports.append(r)
            round_trips.update(rt)
            print(rep.text_summary(r), flush=True)
            if r["overall"]["interrupted"]:
                break
    except Refused as e:
        log(str(e))
        return 4
    except VisceraError as e:
        log(str(e))
        if not reports:
            return 2
    except KeyboardInterrupt:
        log("interrupted")
        if not reports:
            return 2
    if args.json:
        doc = reports[0] if len(args.runs) == 1 else {"runs": reports}
        os.makedirs(os.path.dirname(os.path.abspath(args.json)), exist_ok=True)
        with open(args.json, "w") as f:
            json.dump(doc, f, indent=1)
        log(f"report written to {args.json}")
    if args.plots:
        from viscera_client.load.plots import write_plots
        for p in write_plots(args.plots, reports, round_trips):
            log(f"plot {p}")
    if any(r["overall"]["interrupted"] for r in reports):
        return 2
    if not all(r["overall"]["client_ok"] for r in reports):
        return 3
    return 0 if all(r["overall"]["server_ok"] for r in reports) else 1


if __name__ == "__main__":
    sys.exit(main())
