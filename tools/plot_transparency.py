#!/usr/bin/env python3
"""Draws the transparency curve of the haptic device loop: the force the device rendered during
the press of bench/haptic_bench.sh through 0, 10, 20, 50 and 100 ms of one-way delay, against the
zero-delay force.

    tools/plot_transparency.py OUT_DIR OUT.png

A DOCS-ONLY TOOL: it makes docs/haptic_transparency.png (command in docs/server-benchmarks.md,
"Haptics") and is not part of the build or the tests. It needs matplotlib, which the project does
not otherwise use: `pip install matplotlib`.

OUT_DIR holds delay_<ms>.jsonl, the --log files bench/haptic_bench.sh writes. Left: rendered
vertical force against time for every delay; right: rendered force against the zero-delay force
at the same time (a transparent link is the diagonal).
"""
import bisect
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

DELAYS = (0, 10, 20, 50, 100)


def load(out, delay):
    with open(f"{out}/delay_{delay}.jsonl") as f:
        return [json.loads(line) for line in f]


def main():
    out, png = sys.argv[1], sys.argv[2]
    runs = {d: load(out, d) for d in DELAYS}
    ref = runs[0]
    ref_t = [r["t"] for r in ref]
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for d in DELAYS:
        run = runs[d]
        t = [r["t"] for r in run]
        f = [r["force"][2] for r in run]
        left.plot(t, f, lw=1.0, label=f"{d} ms")
        ref_f = [ref[min(bisect.bisect_left(ref_t, x), len(ref) - 1)]["force"][2] for x in t]
        right.plot(ref_f, f, ".", ms=1.0, label=f"{d} ms")
    left.set_xlabel("time (s)")
    left.set_ylabel("rendered force, vertical (N)")
    left.set_title("press into the tube, 1 kHz session")
    left.legend(title="one-way delay", fontsize=8)
    lim = max(abs(r["force"][2]) for run in runs.values() for r in run) * 1.05
    right.plot([0, lim], [0, lim], "k--", lw=0.8)
    right.set_xlabel("zero-delay force at the same time (N)")
    right.set_ylabel("rendered force (N)")
    right.set_title("transparency (diagonal = transparent)")
    right.set_xlim(-0.05, lim)
    right.set_ylim(-0.05, lim)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main()
