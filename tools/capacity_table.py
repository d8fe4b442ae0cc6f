#!/usr/bin/env python3
"""The capacity table of docs/capacity.md from tools/capacity.sh's reports.

For each configuration (OUT_DIR/<config>/report.json, runs of growing session counts): the
largest count whose run kept deadline misses within 0.1 % of steps and round-trip p99
within one mechanics period, with the figures of that run and of the first run past it.
Usage: tools/capacity_table.py OUT_DIR
"""
import json
import os
import sys


def fmt(v, spec="{:.0f}"):
    return "-" if v is None else spec.format(v)


def row(config, runs):
    runs = sorted(runs, key=lambda r: r["overall"]["sessions"])
    ok = [r for r in runs if r["overall"]["server_ok"] and r["overall"]["client_ok"]]
    best = ok[-1] if ok else None
    past = next((r for r in runs if not (r["overall"]["server_ok"] and r["overall"]["client_ok"])
                 and (best is None or r["overall"]["sessions"] > best["overall"]["sessions"])), None)
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
        cells.append(f"{o['sessions']}: misses {fmt(miss, '{:.2f}')} %, p99 "
                     f"{fmt(o['round_trip_us']['p99'] and o['round_trip_us']['p99'] / 1000, '{:.1f}')} ms, "
                     f"step p50 {fmt(o['step_cost_p50_us'])} us"
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
