#!/usr/bin/env python3
"""A descent paced in real time: the right grasper goes down 5 cm into the pile in `--seconds` at
`--rate` poses per second (Rate keeps the schedule; pump_for would wait a fixed time), with
the force on the hand sampled every half second. Tools are named, positions are numpy
arrays, and a bad pose fails here with a clear error before anything is sent.

  .venv/bin/python examples/paced_descent.py --seconds 4 --rate 200
"""
import argparse
import time

import numpy as np

from viscera_client import Client, PoseError, Rate

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--seconds", type=float, default=4.0)
parser.add_argument("--rate", type=float, default=200.0, help="poses per second")
args = parser.parse_args()

with Client() as client, client.session("cavity", rate_hz=100) as s:
    try:
        s.send_pose("right", (0.0, 0.02))  # a 2-vector: refused here, with the reason
    except PoseError as e:
        print(f"refused locally: {e}")
    top, bottom = np.array([0.105, 0.060, 0.10]), np.array([0.105, 0.060, 0.05])
    n = int(args.seconds * args.rate)
    rate = Rate(args.rate)
    began = time.monotonic()
    for i in range(n + 1):
        s.send_pose("right", top + (bottom - top) * i / n, jaw=1.0)
        if i % int(args.rate / 2) == 0:
            f = s.latest_force("right")
            print(f"t {time.monotonic() - began:5.2f} s  |F| "
                  + ("-" if f is None else f"{np.linalg.norm(f):.3f} N"))
        rate.sleep(client)
    took = time.monotonic() - began
    print(f"descent of {args.seconds:g} s took {took:.2f} s ({rate.missed} ticks missed)")
    final = s.destroy()
    print(f"{final.poses} poses accepted, {final.rejected} rejected, "
          f"{final.deadline_misses} deadline misses")
