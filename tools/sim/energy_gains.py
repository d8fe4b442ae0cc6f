#!/usr/bin/env python3
"""Steps that gain energy without input: each scene at each rate, from viscera-sim's trace.

A scene run without a tool script has no input once it starts (gravity, springs and contacts
are all in the energy), so its total energy must never grow from one step to the next
(docs/contacts.md, "Energy at other rates"). For each scene and rate this prints the steps that
gained more than 1e-6 of the starting energy, the largest gain of one step and when, and the
deepest pair (% of the radius).

Usage, from the repository's root:
  python3 tools/sim/energy_gains.py [--sim build/tools/viscera-sim] [--seconds 3]
      [--rates 100,150,200,250,300,400,500,700,1000] scenes/*.toml
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile


def gains(sim, scene, rate, seconds, trace):
    subprocess.run([sim, scene, "--duration", str(seconds), "--rate", str(rate), "--trace", trace],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(trace) as f:
        frames = [json.loads(line) for line in f]
    start = frames[0]["energy"]["total"]
    steps = [(b["energy"]["total"] - a["energy"]["total"], b["t"]) for a, b in zip(frames, frames[1:])]
    gaining = sum(1 for g, _ in steps if g > 1e-6 * abs(start))
    largest = max(steps)
    deepest = 0.0
    for frame in frames[1:]:
        if frame.get("min_clearance") is not None:
            deepest = max(deepest, -frame["min_clearance"] / frame["sphere_radius"])
    return gaining, largest, 100.0 * deepest


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="+")
    parser.add_argument("--sim", default="build/tools/viscera-sim")
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--rates", default="100,150,200,250,300,400,500,700,1000")
    args = parser.parse_args()
    failed = False
    with tempfile.TemporaryDirectory() as tmp:
        trace = os.path.join(tmp, "trace.jsonl")
        for scene in args.scenes:
            for rate in (float(r) for r in args.rates.split(",")):
                gaining, (largest, when), deepest = gains(args.sim, scene, rate, args.seconds, trace)
                failed |= gaining > 0
                print(f"{os.path.basename(scene):22s} {rate:6.0f} Hz  steps gaining {gaining:3d}  "
                      f"largest step {largest:+.2e} J at t = {when:.3f} s  deepest {deepest:4.1f} % R", flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
