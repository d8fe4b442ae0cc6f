"""The Python client's own checks, without a server: tools by name, poses validated with
clear errors before anything is sent, Status and Force as Python types, pacing that
really waits, and the bus's explanation of an unusable URL."""
import time
import unittest

import numpy as np

import viscera_proto
from viscera_client import (BusError, Client, PoseError, Rate, SessionHandle, SessionState,
                            Status)
from viscera_client.session import Force

MEMQ = "memq://"  # an in-process bus: nothing leaves, nothing needed


def handle():
    return SessionHandle(session_id=42, token=b"t" * 16, server_id="srv", scene="cavity",
                         rate_hz=100.0, tools=["left", "right"])


class PoseValidationTest(unittest.TestCase):
    def setUp(self):
        self.client = Client(MEMQ)
        self.sent = []
        self.client.bus.subscribe("VISCERA_POSE_42", viscera_proto.tool_pose_t,
                                  lambda p, chan, t: self.sent.append(p))

    def tearDown(self):
        self.client.close()

    def error(self, **pose):
        with self.assertRaises(PoseError) as e:
            self.client.send_pose(handle(), **pose)
        return str(e.exception)

    def test_tools_by_name_or_index(self):
        self.client.send_pose(handle(), "right", (0.0, 0.02, 0.1), jaw=0.5)
        self.client.send_pose(handle(), 0, np.array([0.0, 0.0, 0.1]))
        self.client.pump(0.1)
        self.client.pump(0.1)
        self.assertEqual([p.tool for p in self.sent], [1, 0])
        self.assertEqual(self.sent[0].jaw, 0.5)

    def test_bad_values_are_named_before_anything_is_sent(self):
        self.assertIn("no tool 'Right' in session 42 (its tools: 0: left, 1: right); did you "
                      "mean 'right'?", self.error(tool="Right", position=(0, 0, 0.1)))
        self.assertIn("tool 7 does not exist: session 42 has 2 tool(s)",
                      self.error(tool=7, position=(0, 0, 0.1)))
        self.assertIn("position (x, y, z in m) must be 3 numbers, got 2",
                      self.error(tool="right", position=(0.0, 0.1)))
        self.assertIn("beyond 10 m", self.error(tool="right", position=(50.0, 0.0, 0.0)))
        self.assertIn("non-finite", self.error(tool="right", position=(float("nan"), 0, 0)))
        self.assertIn("jaw 1.5 must be within [0, 1]",
                      self.error(tool="right", position=(0, 0, 0.1), jaw=1.5))
        self.assertIn("not a rotation",
                      self.error(tool="right", position=(0, 0, 0.1), orientation=(0, 0, 0, 0)))
        self.assertIn("must be 3 numbers", self.error(tool="right", position="abc"))
        self.assertIsInstance(PoseError("x"), ValueError)
        self.client.pump(0.1)
        self.assertEqual(self.sent, [])  # nothing reached the bus

    def test_create_arguments_are_checked(self):
        with self.assertRaisesRegex(ValueError, "create needs a scene: a name"):
            self.client.create()
        with self.assertRaisesRegex(ValueError, "not both"):
            self.client.create("cavity", scene_toml="[simulation]")
        with self.assertRaisesRegex(ValueError, "rate_hz 5000 must be within 0..1000"):
            self.client.create("cavity", rate_hz=5000)

    def test_camera_is_checked(self):
        with self.assertRaisesRegex(PoseError, "same point"):
            self.client.camera(handle(), (0, 0, 0.2), (0, 0, 0.2))
        with self.assertRaisesRegex(PoseError, "camera eye"):
            self.client.camera(handle(), (0, 0, 20.0), (0, 0, 0))


class TypesTest(unittest.TestCase):
    def test_status_is_a_dataclass_with_an_enum_state_and_the_rest_reads_through(self):
        msg = viscera_proto.session_status_t()
        msg.header = viscera_proto.header_t()
        msg.header.session_id = 42
        msg.server_id, msg.scene = "srv", "cavity"
        msg.num_tools, msg.tool_names = 2, ["left", "right"]
        msg.state = viscera_proto.session_status_t.kPaused
        msg.energy = 1.5
        st = Status.from_message(msg)
        self.assertIs(st.state, SessionState.PAUSED)
        self.assertEqual(st.tools, ["left", "right"])
        self.assertEqual(st.energy, 1.5)  # not a dataclass field: from the message
        with self.assertRaises(AttributeError):
            st.no_such_field
        self.assertIs(SessionState.of(9), SessionState.UNKNOWN)

    def test_force_holds_numpy_arrays(self):
        f = viscera_proto.force_feedback_t()
        f.force = [1.0, 2.0, 3.0]
        f.stiffness = [[1.0, 0, 0], [0, 2.0, 0], [0, 0, 3.0]]
        ff = Force.from_message(f)
        self.assertEqual(ff.force.shape, (3,))
        self.assertEqual(ff.stiffness.shape, (3, 3))
        np.testing.assert_array_equal(ff.force, [1.0, 2.0, 3.0])


class PacingTest(unittest.TestCase):
    # lower bounds only: a wait never ends early, however loaded the machine
    def test_pump_for_waits_the_whole_time(self):
        with Client(MEMQ) as c:
            start = time.monotonic()
            c.pump_for(0.2)
            self.assertGreaterEqual(time.monotonic() - start, 0.2)

    def test_rate_paces_a_loop(self):
        with Client(MEMQ) as c:
            rate = Rate(50)
            start = time.monotonic()
            for _ in range(10):
                rate.sleep(c)
            self.assertGreaterEqual(time.monotonic() - start, 10 / 50 - 1e-3)
        with self.assertRaisesRegex(ValueError, "positive rate"):
            Rate(0)

    def test_spin_until(self):
        with Client(MEMQ) as c:
            hits = []
            self.assertFalse(c.spin_until(lambda: bool(hits), 0.1))
            self.assertTrue(c.spin_until(lambda: True, 0.1))


class BusErrorTest(unittest.TestCase):
    def test_an_unusable_url_is_explained(self):
        with self.assertRaises(BusError) as e:
            Client("udpm://999.1.1.1:7667?ttl=0")
        self.assertIn("multicast route", str(e.exception))
        self.assertIn("udpm://999.1.1.1:7667", str(e.exception))


if __name__ == "__main__":
    unittest.main()
