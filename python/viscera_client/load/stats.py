"""What one session's load test measures, and the summaries of it. Pure Python: no LCM."""
import math


def percentile(sorted_values, q):
    """Nearest-rank percentile of an ascending list (q in 0..100); None when empty."""
    if not sorted_values:
        return None
    rank = max(1, math.ceil(q / 100.0 * len(sorted_values)))
    return sorted_values[min(rank, len(sorted_values)) - 1]


def latency_summary(values):
    """{count, p50, p95, p99, max, mean} of a list of numbers (None entries when empty)."""
    v = sorted(values)
    return {
        "count": len(v),
        "p50": percentile(v, 50), "p95": percentile(v, 95), "p99": percentile(v, 99),
        "max": v[-1] if v else None,
        "mean": sum(v) / len(v) if v else None,
    }


class SeqCounter:
    """Messages of one stream received, and lost: the sequence numbers missing between
    the first and the last one received (one that arrives late fills its gap; one that
    arrives twice counts once)."""

    def __init__(self):
        self.first = None
        self.last = None
        self.received = 0
        self._seen = set()

    def add(self, seq):
        self.first = seq if self.first is None else min(self.first, seq)
        self.last = seq if self.last is None else max(self.last, seq)
        self.received += 1
        self._seen.add(seq)

    @property
    def lost(self):
        if self.first is None:
            return 0
        return (self.last - self.first + 1) - len(self._seen)


class SessionProbe:
    """Everything measured about one session during a load test (one worker owns it).

    Round trip: a force echoes the pose it used (pose_seq, pose_utime = the pose's send
    time); the first force that echoes a new pose gives that pose's round trip, receive
    time minus send time on this machine's clock.
    """

    def __init__(self, handle, tool, pose_period_s, start_mono, next_pose=None, max_echoed=-1,
                 poses_sent_warmup=0):
        self.handle = handle
        self.tool = tool
        self.period = pose_period_s
        self.start = start_mono
        self.next_pose = start_mono if next_pose is None else next_pose
        self.poses_sent = 0
        self.poses_sent_warmup = poses_sent_warmup  # sent before the measurement began
        self.ticks_skipped = 0          # pose ticks this client was too late to send
        self.send_lateness_us = []      # how late each pose left after its tick
        self.round_trips_us = []
        self.max_echoed = max_echoed
        self.poses_answered = 0
        self.forces = SeqCounter()
        self.frames = SeqCounter()
        self.frame_ages_ms = []         # sent - snapshot (server side)
        self.frame_delays_ms = []       # received - sent
        self.statuses = []              # (t s since start, status fields), see on_status
        self.per_second = {}            # second -> [poses sent, forces, round trips]

    def begin_measurement(self, start_mono):
        """Forgets what the warm-up measured (keeping its pose count for the loss balance
        and the last pose answered); times count from `start_mono` on."""
        self.poses_sent_warmup += self.poses_sent
        self.__init__(self.handle, self.tool, self.period, start_mono,
                      next_pose=self.next_pose, max_echoed=self.max_echoed,
                      poses_sent_warmup=self.poses_sent_warmup)

    def _bucket(self, t_mono):
        return self.per_second.setdefault(int(t_mono - self.start), [0, 0, []])

    def on_pose_sent(self, tick_mono, now_mono):
        self.poses_sent += 1
        self.send_lateness_us.append((now_mono - tick_mono) * 1e6)
        self._bucket(now_mono)[0] += 1

    def on_force(self, seq, tool, pose_seq, pose_utime, recv_utime, now_mono):
        self.forces.add(seq)
        bucket = self._bucket(now_mono)
        bucket[1] += 1
        if tool == self.tool and pose_seq > self.max_echoed:
            self.max_echoed = pose_seq
            self.poses_answered += 1
            rtt = recv_utime - pose_utime
            self.round_trips_us.append(rtt)
            bucket[2].append(rtt)

    def on_frame(self, seq, utime, snapshot_utime, recv_utime):
        self.frames.add(seq)
        self.frame_ages_ms.append((utime - snapshot_utime) / 1000.0)
        self.frame_delays_ms.append((recv_utime - utime) / 1000.0)

    def on_status(self, status, now_mono):
        self.statuses.append((now_mono - self.start, status_fields(status)))

    def timeline(self, elapsed_s):
        """Per second of the run, up to its end (the last second counts when the run
        streamed through most of it: a 10 s run ends a few ms short of 10.0): poses sent,
        forces received, round-trip p99 (us)."""
        out = []
        for second in sorted(s for s in self.per_second if s + 0.5 <= elapsed_s):
            poses, forces, rtts = self.per_second[second]
            out.append({"t": second, "poses": poses, "forces": forces,
                        "round_trip_p99_us": percentile(sorted(rtts), 99)})
        return out


STATUS_FIELDS = ("steps", "deadline_misses", "achieved_rate_hz", "rate_hz", "step_cost_p50_us",
                 "step_cost_p99_us", "jitter_p99_us", "step_wall_max_us", "poses", "rejected",
                 "frames", "frames_dropped", "achieved_frame_rate_hz", "frame_rate_hz",
                 "skin_ms", "render_ms", "encode_ms", "state")


def status_fields(status):
    """The numbers of a session_status_t a load test keeps (a plain dict)."""
    return {k: getattr(status, k) for k in STATUS_FIELDS}
