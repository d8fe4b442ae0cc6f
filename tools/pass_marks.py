#!/usr/bin/env python3
"""Pass marks for running the bowel from a cohort of experts' reports (docs/training.md).

Commercial trainers set a metric's pass mark at the experts' mean + 1 SD. Give the reports of
the experts' runs (`viscera report --json`, or `viscera-sim --report`), at least two; prints each
mark's mean, SD and mean + 1 SD, and the `[running]` keys to paste into the scene:
  tools/pass_marks.py expert1.json expert2.json ...
A run that missed a segment, hurt the bowel, slipped too often or turned back is refused: a
mark drawn from a failed run would let the next one fail the same way.
"""
import argparse
import json
import statistics
import sys

# (scene key, report key, unit, decimals)
MARKS = (
    ("pass_time", "time_s", "s", 1),
    ("pass_path", "path_length_m", "m", 2),
    ("pass_out_of_view", "out_of_view_time_s", "s", 1),
)


def running(path):
    with open(path) as f:
        report = json.load(f)
    run = report.get("running")
    if not run:
        sys.exit(f"{path}: no running-the-bowel section (a scene without [running]?)")
    lapses = [name for name in ("coverage", "damage", "slips", "reversals") if name in run["failed"]]
    if lapses:
        sys.exit(f"{path}: not an expert's run: failed on {', '.join(lapses)}")
    return run


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("reports", nargs="+", help="the experts' reports (JSON)")
    a = ap.parse_args()
    if len(a.reports) < 2:
        ap.error("give at least two experts' reports: one run has no SD")
    runs = [running(p) for p in a.reports]
    keys = []
    for key, field, unit, decimals in MARKS:
        values = [r[field] for r in runs]
        mean, sd = statistics.mean(values), statistics.stdev(values)
        mark = round(mean + sd, decimals)
        print(f"{field:20s} mean {mean:.{decimals + 1}f} {unit}, SD {sd:.{decimals + 1}f} {unit} "
              f"over {len(values)} runs: pass at {mark} {unit}")
        keys.append(f"{key} = {mark}")
    print("\n[running]\n" + "\n".join(keys))


if __name__ == "__main__":
    main()
