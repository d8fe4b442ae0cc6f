#!/usr/bin/env python3
"""Prints a session's target exposure as viscerad reports it in the session's status messages
(docs/assessment.md), one line each time it changes, until the session stops or this is
terminated: the demo shows the lesion going from hidden to exposed with it.

    watch_exposure.py SESSION_ID [--lcm-url URL]
"""
import argparse
import signal
import sys

import viscera_proto
from viscera_client import Client
from viscera_client.client import session_channel


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("session", type=int)
    parser.add_argument("--lcm-url", default=None)
    args = parser.parse_args()
    running = [True]
    signal.signal(signal.SIGTERM, lambda *_: running.__setitem__(0, False))
    last = [None]

    def on_status(s, channel, utime):
        exposed = tuple(round(s.target_exposed[i], 4) for i in range(s.num_targets))
        if exposed != last[0]:
            last[0] = exposed
            names = " ".join(f"{s.target_names[i]} {100 * e:5.1f} % exposed" for i, e in enumerate(exposed))
            print(f"   exposure at t = {s.sim_time:5.2f} s: {names or 'no target'}", flush=True)
        if s.state == viscera_proto.session_status_t.kStopped:
            running[0] = False

    with Client(url=args.lcm_url) as client:
        client.bus.subscribe(session_channel("STATUS", args.session), viscera_proto.session_status_t, on_status)
        while running[0]:
            client.pump(0.1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
