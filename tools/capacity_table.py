#!/usr/bin/env python3
"""The capacity table of docs/capacity.md from tools/capacity.sh's reports.

For each configuration (OUT_DIR/<config>/report.json, runs of growing session counts): the
last count before the first run past the limits of viscera_client.load.report (deadline
misses within 0.1 % of steps, round-trip p99 within two periods, frames at 90 % of their
rate, the client keeping its pose rate), with the figures of that run and of the first run
past them.
Usage: tools/capacity_table.py OUT_DIR
"""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "python"))
from viscera_client.load.report import server_problems  # noqa: E402


def within_limits(run):
    """The run judged again from its figures, with the criteria of this checkout."""
    return run["overall"]["client_ok"] and not any(server_problems(s) for s in run["sessions"])


def fmt(v, spec="{:.0f}"):
    return "-" if v is None else spec.format(v)


def row(config, runs):
    runs = sorted(runs, key=lambda r: r["overall"]["sessions"])
    # the capacity is the last count before the first run past the limits (conservative: a
    # machine shared with other work misses now and then, and a pass after a failure is luck)
    past = next((r for r in runs if not within_limits(r)), None)
    before = [r for r in runs if past is None or r["overall"]["sessions"] < past["overall"]["sessions"]]
    best = before[-1] if before else None
    client_limited = past is not None and not past["overall"]["client_ok"]
    cells = [config]
    if best is None:
        cells.append("0" + (" (client-limited)" if client_limited else ""))
    else:
        n = str(best["overall"]["sessions"])
        if past is None:
            n = f"≥ {n}"  # never crossed within the sweep
        cells.append(n + (" (client-limited)" if client_limited else ""))
    for r in (best, past):
        if r is None:
            cells.append("-")
            continue
        o = r["overall"]
        miss = None if o["miss_fraction"] is None else 100.0 * o["miss_fraction"]
        p99 = o["round_trip_us"]["p99"]
        frames = ""
        if o["frames"]:
            frames = f", frames ≥ {o['frames']['rate_hz_min']:.1f} Hz"
        cells.append(f"{o['sessions']}: misses {fmt(miss, '{:.2f}')} %, p99 "
                     f"{fmt(None if p99 is None else p99 / 1000, '{:.1f}')} ms, "
                     f"step p50 {fmt(o['step_cost_p50_us'])} us{frames}"
                     + ("" if o["client_ok"] else ", client late"))
    return "| " + " | ".join(cells) + " |"


def main(out):
    lines = ["| configuration | sessions per core | last run within limits | first run past them |",
             "|---|---|---|---|"]
    for config in sorted(os.listdir(out)):
        path = os.path.join(out, config, "report.json")
        if not os.path.exists(path):
            continue
        with open(path) as f:
            doc = json.load(f)
        lines.append(row(config, doc.get("runs", [doc])))
    print("\n".join(lines))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/capacity")
