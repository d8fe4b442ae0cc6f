"""Unit tests of the Python client's parts that need no network: the MAC (against its
definition and by tampering), the fast partial decoders (against lcm-gen's full decode),
placement, the load tester's statistics and the pass marks drawn from experts' reports."""
import dataclasses
import hashlib
import hmac
import json
import os
import random
import struct
import subprocess
import sys
import tempfile
import unittest

import viscera_proto
from viscera_client import MessageAuth, ServerInfo, Status, make_header, pick_server, report_from_status
from viscera_client.directory import observe
from viscera_client.auth import mac_len_offset
from viscera_client.fast import force_echo, frame_times
from viscera_client.load.stats import SeqCounter, latency_summary, percentile


def force_message(seq, tool, pose_seq, pose_utime, token=b"\x07" * 16):
    f = viscera_proto.force_feedback_t()
    f.header = make_header(1234, seq, token)
    f.tool = tool
    f.step = 99
    f.sim_time = 0.5
    f.force = [1.0, -2.0, 3.5]
    f.torque = [0.1, 0.2, 0.3]
    f.stiffness = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]]
    f.tip = [0.01, 0.02, 0.03]
    f.pose_seq = pose_seq
    f.pose_utime = pose_utime
    f.clamped = False
    f.active = True
    f.grasping = False
    return f


class AuthTest(unittest.TestCase):
    key = bytes(range(32))

    def test_mac_is_hmac_sha512_256_over_the_unsigned_message(self):
        data = force_message(5, 0, 4, 17).encode()
        signed = MessageAuth(self.key).sign(data)
        offset = mac_len_offset(data)
        self.assertEqual(len(signed), len(data) + 32)
        self.assertEqual(struct.unpack_from(">i", signed, offset)[0], 32)
        expected = hmac.new(self.key, data, hashlib.sha512).digest()[:32]
        self.assertEqual(signed[offset + 4:offset + 36], expected)
        # still a valid message of its type: the header's mac field holds it
        decoded = viscera_proto.force_feedback_t.decode(signed)
        self.assertEqual(decoded.header.mac, expected)
        self.assertEqual(decoded.pose_seq, 4)

    def test_every_flipped_byte_fails_verification(self):
        auth = MessageAuth(self.key)
        signed = auth.sign(force_message(5, 0, 4, 17).encode())
        self.assertTrue(auth.verify(signed))
        for i in range(len(signed)):
            tampered = bytearray(signed)
            tampered[i] ^= 0x01
            self.assertFalse(auth.verify(bytes(tampered)), f"byte {i}")
        self.assertFalse(MessageAuth(bytes(32)).verify(signed))  # another key
        self.assertFalse(auth.verify(force_message(5, 0, 4, 17).encode()))  # unsigned
        self.assertFalse(auth.verify(b"short"))

    def test_key_file_is_blake2b_of_its_content(self):
        import tempfile
        with tempfile.NamedTemporaryFile("wb") as f:
            f.write(b"0123456789abcdef0123")
            f.flush()
            a = MessageAuth.from_key_file(f.name)
        self.assertEqual(a._key, hashlib.blake2b(b"0123456789abcdef0123", digest_size=32).digest())
        with tempfile.NamedTemporaryFile("wb") as f:
            f.write(b"too short")
            f.flush()
            with self.assertRaises(ValueError):
                MessageAuth.from_key_file(f.name)


class FastDecodeTest(unittest.TestCase):
    def test_force_echo_matches_full_decode(self):
        rng = random.Random(7)
        auth = MessageAuth(bytes(32))
        for i in range(200):
            token = bytes(rng.randrange(256) for _ in range(rng.choice([0, 16])))
            m = force_message(rng.randrange(1 << 40), rng.randrange(3), rng.randrange(-1, 1 << 40),
                              rng.randrange(1 << 52), token)
            data = m.encode()
            if i % 2:
                data = auth.sign(data)
            full = viscera_proto.force_feedback_t.decode(data)
            self.assertEqual(force_echo(data), (full.header.version, full.header.seq, full.tool,
                                                full.pose_seq, full.pose_utime))

    def test_frame_times_match_full_decode(self):
        f = viscera_proto.jpeg_frame_t()
        f.header = make_header(9, 41, b"\x01" * 16)
        f.step, f.sim_time, f.snapshot_utime, f.dropped = 10, 0.1, 1700000000000001, 2
        f.skin_ms = f.render_ms = f.encode_ms = 1.0
        f.width, f.height = 4, 2
        f.data = b"\xff\xd8jpeg\xff\xd9"
        f.size = len(f.data)
        data = f.encode()
        self.assertEqual(frame_times(data), (f.header.version, 41, f.header.utime, f.snapshot_utime))

    def test_other_types_and_truncations_are_refused(self):
        data = force_message(1, 0, 0, 0).encode()
        hb = viscera_proto.heartbeat_t()
        hb.header = make_header()
        hb.server_id, hb.num_sessions, hb.max_sessions = "s", 0, 1
        hb.load, hb.uptime_us, hb.rejected = 0.0, 0, 0
        self.assertIsNone(force_echo(hb.encode()))
        self.assertIsNone(frame_times(data))
        for cut in range(len(data)):
            self.assertIsNone(force_echo(data[:cut]), cut)


class PlacementTest(unittest.TestCase):
    def test_emptiest_share_then_load_then_id(self):
        a = ServerInfo("a", sessions=2, max_sessions=4, load=0.1)
        b = ServerInfo("b", sessions=1, max_sessions=4, load=0.9)
        self.assertEqual(pick_server([a, b]).server_id, "b")
        big = ServerInfo("big", sessions=4, max_sessions=16, load=2.0)  # a quarter full
        self.assertEqual(pick_server([a, b, big]).server_id, "b")       # also a quarter: lower load
        c = ServerInfo("c", sessions=1, max_sessions=4, load=0.9)
        self.assertEqual(pick_server([c, b]).server_id, "b")            # tie: smaller id

    def test_full_servers_are_skipped(self):
        full = ServerInfo("full", sessions=3, max_sessions=3)
        self.assertIsNone(pick_server([full]))
        self.assertIsNone(pick_server([]))
        self.assertEqual(pick_server([full, ServerInfo("x", 7, 8, 1.5)]).server_id, "x")


class StatsTest(unittest.TestCase):
    def test_percentiles_are_nearest_rank(self):
        v = list(range(1, 101))
        self.assertEqual(percentile(v, 50), 50)
        self.assertEqual(percentile(v, 99), 99)
        self.assertEqual(percentile(v, 100), 100)
        self.assertEqual(percentile([5], 99), 5)
        self.assertIsNone(percentile([], 50))
        s = latency_summary([3, 1, 2])
        self.assertEqual((s["p50"], s["max"], s["count"]), (2, 3, 3))

    def test_seq_counter_counts_gaps_once(self):
        c = SeqCounter()
        for seq in [10, 11, 13, 14, 12, 14, 17]:
            c.add(seq)
        # 10..17 is 8 messages; 15 and 16 never came; 12 came late, 14 twice
        self.assertEqual(c.lost, 2)
        self.assertEqual(SeqCounter().lost, 0)


class AssessmentTest(unittest.TestCase):
    def test_report_from_a_status_through_the_wire(self):
        s = viscera_proto.session_status_t()
        s.header = make_header(7, 0)
        s.scene, s.sim_time, s.state = "cavity", 4.5, s.kStopped
        s.num_tools, s.tool_names = 1, ["left"]
        s.tool_path_length, s.tool_active_time = [0.3], [4.5]
        s.tool_force_p50, s.tool_force_p95, s.tool_force_max = [0.58], [0.99], [1.09]
        s.tool_contact_time, s.tool_traction_events, s.tool_traction_time = [3.4], [2], [1.25]
        s.tool_grasps, s.tool_regrasps = [3], [1]
        s.tool_organ_contacts, s.tool_organ_contact_time = [4], [0.07]
        s.num_targets, s.target_names = 2, ["lesion", "other"]
        s.target_exposed, s.target_max_exposed, s.target_time_to_expose = [1.0, 0.1], [1.0, 0.2], [2.0, -1.0]
        s.traction_force, s.traction_hold, s.regrasp_window, s.exposed_fraction = 3.0, 0.5, 1.0, 0.9
        r = report_from_status(viscera_proto.session_status_t.decode(s.encode()))
        self.assertEqual(r["session"], 7)
        self.assertTrue(r["finished"])
        self.assertEqual(r["thresholds"], {"traction_force_n": 3.0, "traction_hold_s": 0.5,
                                           "regrasp_window_s": 1.0, "exposed_fraction": 0.9})
        self.assertEqual(r["tools"][0]["tissue_force_n"], {"p50": 0.58, "p95": 0.99, "max": 1.09})
        self.assertEqual((r["tools"][0]["traction_events"], r["tools"][0]["grasps"],
                          r["tools"][0]["regrasps"]), (2, 3, 1))
        self.assertEqual(r["targets"][0]["time_to_expose_s"], 2.0)
        self.assertIsNone(r["targets"][1]["time_to_expose_s"])  # not exposed: null, as in C++
        self.assertIsNone(r["running"])  # no [running]: null, as in C++

    def test_running_the_bowel_from_a_status_through_the_wire(self):
        s = viscera_proto.session_status_t()
        s.header = make_header(8, 0)
        s.scene, s.state = "bowel_run", s.kRunning
        s.running_segments, s.running_segment_length, s.running_coverage = 90, 0.05, 2.0 / 90.0
        s.running_num_missed, s.running_missed = 88, list(range(2, 90))
        s.running_grasps, s.running_slips, s.running_max_grip = 2, 1, 20.0
        s.running_num_events = 1
        s.running_event_kinds, s.running_event_segments, s.running_event_tools = ["pinch"], [0], ["left"]
        s.running_event_times, s.running_event_values = [1.52], [20.0]
        s.running_num_damaged, s.running_damaged = 1, [0]
        s.running_num_failed, s.running_failed = 2, ["coverage", "damage"]
        s.running_pinch_force, s.running_pass_coverage, s.running_pass_slips = 10.3, 1.0, 2
        s.running_pass_out_of_view = 21.5
        r = report_from_status(viscera_proto.session_status_t.decode(s.encode()))["running"]
        self.assertEqual((r["segments"], r["grasps"], r["slips"]), (90, 2, 1))
        self.assertEqual(r["missed"], list(range(2, 90)))
        self.assertEqual(r["events"], [{"kind": "pinch", "segment": 0, "tool": "left", "t_s": 1.52,
                                        "value": 20.0}])
        self.assertEqual(r["damaged"], [0])
        self.assertEqual(r["failed"], ["coverage", "damage"])
        self.assertFalse(r["passed"])
        self.assertEqual(r["thresholds"]["pinch_force_n"], 10.3)
        self.assertEqual(r["pass_marks"]["slips"], 2)
        self.assertEqual(r["pass_marks"]["out_of_view_time_s"], 21.5)


class PassMarksTest(unittest.TestCase):
    """tools/pass_marks.py: the experts' mean + 1 SD of each mark, from their reports."""

    def run_tool(self, runs):
        with tempfile.TemporaryDirectory() as d:
            paths = []
            for i, run in enumerate(runs):
                paths.append(os.path.join(d, f"expert{i}.json"))
                with open(paths[-1], "w") as f:
                    json.dump({"running": run}, f)
            tool = os.path.join(os.environ["VISCERA_SOURCE_DIR"], "tools", "pass_marks.py")
            return subprocess.run([sys.executable, tool] + paths, capture_output=True, text=True)

    @staticmethod
    def expert(time, path, out_of_view, failed=()):
        return {"time_s": time, "path_length_m": path, "out_of_view_time_s": out_of_view,
                "failed": list(failed)}

    def test_each_mark_is_the_experts_mean_plus_one_sd(self):
        done = self.run_tool([self.expert(140.0, 16.0, 17.0), self.expert(150.0, 17.0, 19.0),
                              self.expert(145.0, 18.0, 21.0)])
        self.assertEqual(done.returncode, 0, done.stderr)
        keys = dict(line.split(" = ") for line in done.stdout.splitlines() if " = " in line)
        # means 145 s, 17 m, 19 s; sample SDs 5 s, 1 m, 2 s
        self.assertEqual(keys, {"pass_time": "150.0", "pass_path": "18.0", "pass_out_of_view": "21.0"})

    def test_a_failed_run_or_a_single_run_is_refused(self):
        hurt = self.expert(150.0, 17.0, 19.0, failed=["damage"])
        refused = self.run_tool([self.expert(140.0, 16.0, 17.0), hurt])
        self.assertNotEqual(refused.returncode, 0)
        self.assertIn("failed on damage", refused.stderr)
        self.assertNotEqual(self.run_tool([self.expert(140.0, 16.0, 17.0)]).returncode, 0)


class SolverCountTest(unittest.TestCase):
    def test_status_carries_unconverged_solves_through_the_wire(self):
        s = viscera_proto.session_status_t()
        s.header = make_header(9, 0)
        s.scene, s.state, s.unconverged_solves, s.record_failures = "fall", s.kRunning, 37, 2
        status = Status.from_message(viscera_proto.session_status_t.decode(s.encode()))
        # a field of the dataclass itself (in its repr and fields), not only read through `raw`
        self.assertIn("unconverged_solves", [f.name for f in dataclasses.fields(Status)])
        self.assertEqual(status.__dict__["unconverged_solves"], 37)
        self.assertEqual(status.unconverged_solves, 37)
        self.assertEqual(status.record_failures, 2)  # the field before it, read through raw

    def test_heartbeat_carries_the_servers_total(self):
        hb = viscera_proto.heartbeat_t()
        hb.header = make_header(0, 0)
        hb.server_id, hb.num_sessions, hb.max_sessions = "a", 1, 4
        hb.not_ours, hb.unconverged_solves = 3, 1234567890123
        servers = {}
        observe(servers, viscera_proto.heartbeat_t.decode(hb.encode()))
        self.assertEqual(servers["a"].unconverged_solves, 1234567890123)
        self.assertEqual(servers["a"].not_ours, 3)


if __name__ == "__main__":
    unittest.main()
