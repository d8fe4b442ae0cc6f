#!/usr/bin/env python3
"""A first session from Python: create one on the least loaded server, lower the right
grasper 5 cm onto the intestine at 100 Hz for two seconds, read the force on the hand, pause,
look from another camera, reset, and leave (the `with` block destroys the session).

  .venv/bin/python examples/first_session.py            # a viscerad must be running
"""
import numpy as np

from viscera_client import Client, Rate, SessionState

with Client() as client:
    with client.session("cavity") as s:
        print(f"session {s.id} on {s.server_id}: tools {s.tools}, {s.rate_hz:g} Hz")
        start = np.array([0.105, 0.060, 0.10])  # above the loop over the lesion
        rate = Rate(100)
        for i in range(200):  # 2 s: 5 cm down, into the pile
            s.send_pose("right", start - [0.0, 0.0, 0.00025 * i], jaw=1.0)
            rate.sleep(client)  # paces the loop, handling forces meanwhile
        force = s.latest_force("right")
        print(f"force on the hand: {np.round(force, 3)} N (|F| = {np.linalg.norm(force):.3f} N)")

        s.pause()
        client.spin_until(lambda: s.status().state is SessionState.PAUSED, timeout_s=5.0)
        st = s.status()
        print(f"paused at t = {st.sim_time:.2f} s after {st.steps} steps, "
              f"{st.deadline_misses} deadline misses, {st.poses} poses accepted")
        s.camera(eye=(-0.02, -0.14, 0.20), target=(-0.01, 0.01, 0.05))
        s.resume()
        s.reset()
        client.spin_until(lambda: s.status().state is SessionState.RUNNING, timeout_s=5.0)
        print(f"state {s.status().state.name}")
print("session destroyed")
