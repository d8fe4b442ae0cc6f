"""examples/*.py against a real viscerad in a private network namespace: each runs to its
end (exit 0) with the output it promises, and leaves no session behind (the `with` blocks
destroy them)."""
import os
import subprocess
import sys
import unittest

from netns_support import SOURCE_DIR, URL, Server, new_client, require_private_netns, wait_for_servers

EXAMPLES = os.path.join(SOURCE_DIR, "examples")


class ExamplesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        require_private_netns()
        cls.server = Server("py-ex", "--max-sessions", "2")
        cls.client = new_client()
        wait_for_servers(cls.client, ["py-ex"])

    @classmethod
    def tearDownClass(cls):
        assert cls.server.stop() == 0, cls.server.stderr()

    def run_example(self, name, *args):
        run = subprocess.run([sys.executable, os.path.join(EXAMPLES, name), *args],
                             env=dict(os.environ, LCM_DEFAULT_URL=URL), capture_output=True,
                             text=True, timeout=120)
        self.assertEqual(run.returncode, 0, f"{name}\n{run.stdout}\n{run.stderr}\n"
                                             f"{self.server.stderr()[-3000:]}")
        self.assertEqual(wait_for_servers(self.client, ["py-ex"])["py-ex"].sessions, 0,
                         "a session was left behind")
        return run.stdout

    def test_every_example_is_tested(self):
        self.assertEqual(sorted(f for f in os.listdir(EXAMPLES) if f.endswith(".py")),
                         ["first_session.py", "paced_descent.py"])

    def test_first_session(self):
        out = self.run_example("first_session.py")
        self.assertRegex(out, r"session \d+ on py-ex: tools \['left', 'right'\], 100 Hz")
        self.assertRegex(out, r"force on the hand: \[.*\] N")
        self.assertIn("paused at t = ", out)
        self.assertIn("state RUNNING", out)
        self.assertIn("session destroyed", out)

    def test_paced_descent_takes_its_time(self):
        out = self.run_example("paced_descent.py", "--seconds", "2", "--rate", "100")
        self.assertIn("refused locally: position (x, y, z in m) must be 3 numbers, got 2", out)
        took = float(out.split("took ")[1].split(" s")[0])
        self.assertGreaterEqual(took, 2.0)  # Rate never runs ahead (a lower bound: not timed)
        self.assertRegex(out, r"201 poses accepted, 0 rejected")


if __name__ == "__main__":
    unittest.main()
