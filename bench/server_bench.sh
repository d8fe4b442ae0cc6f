#!/bin/sh
# Server benchmark (not a timed test): runs the real viscerad and viscera over real UDP
# multicast inside a private loopback-only network namespace and prints the figures that
# docs/server-benchmarks.md ("Server") records:
#  1. round trip pose -> force (p50/p99) at a 1 kHz pose rate, mechanics at 100 Hz and 1 kHz,
#     on the 250-point intestine of scenes/fall.toml (contacts with the floor) plus one tool;
#  2. deadline misses at 100 Hz and 1 kHz over the drive;
#  3. the clinical scene (cavity.toml with its clearing gesture) at 100 Hz and 1 kHz: misses, cost;
#  4. how many concurrent 100 Hz sessions of scenes/fall.toml run without deadline misses.
# Sessions here stream no frames (--frame-rate -1): bench/frames_bench.sh measures those.
# Usage: bench/server_bench.sh [BUILD_DIR] [MAX_SESSIONS] [REALTIME_PRIORITY]
# VISCERA_BENCH_NETNS=0 runs on the host's network (ttl=0: nothing leaves the machine): the
# namespace is a user namespace here, which refuses --realtime's SCHED_FIFO.
set -eu
. "$(dirname "$0")/netns_server.sh"
build=${1:-$root/build}
max_sessions=${2:-12}
realtime=${3:-0}
echo "== $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg), viscerad --realtime $realtime"
start_server --server-id bench --max-sessions 64 --realtime "$realtime"

# the 250-point fall with a grasper pressing down into the pile as it lands
{ cat "$root/scenes/fall.toml"; printf '\n[[tool]]\nname = "probe"\nport = [0.0, 0.0, 0.4]\n'; } >"$work/fall_tool.toml"
cat >"$work/press.csv" <<'CSV'
t,tool,x,y,z,qw,qx,qy,qz,jaw
0,probe,0.10,0.0,0.20,1,0,0,0,1
2,probe,0.10,0.0,0.03,1,0,0,0,1
5,probe,0.10,0.0,0.02,1,0,0,0,1
6,probe,-0.10,0.0,0.02,1,0,0,0,1
CSV

echo "== round trip and deadline misses (250 points, contacts, 1 tool, poses at 1 kHz for 6 s)"
for rate in 100 1000; do
  id=$(new_session --scene-file "$work/fall_tool.toml" --rate $rate --frame-rate -1)
  sleep 1
  v drive "$id" --script "$work/press.csv" --pose-rate 1000 --json >"$work/drive.json"
  python3 - "$work/drive.json" "$rate" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); r, s = d["drive"], d["status"]
print(f"mechanics {sys.argv[2]:>4} Hz: round trip p50 {r['round_trip_p50_us']:.0f} us, p99 {r['round_trip_p99_us']:.0f} us, "
      f"max {r['round_trip_max_us']:.0f} us ({r['poses_answered']} of {r['poses_sent']} poses answered); "
      f"max |F| {r['max_force_n']:.2f} N; achieved {s['rate_hz']:.1f} Hz; "
      f"deadline misses {s['deadline_misses']} of {s['steps']} steps ({100.0 * s['deadline_misses'] / max(1, s['steps']):.3f} %); "
      f"step p50 {s['step_cost_p50_us']:.0f} us p99 {s['step_cost_p99_us']:.0f} us, longest (wall, last 0.25 s) {s['step_wall_max_us']:.0f} us; jitter p99 {s['jitter_p99_us']:.0f} us; contacts {s['contacts']}")
PY
  v destroy "$id" >/dev/null
done

echo "== the clinical scene: scenes/cavity.toml played with scenes/clearing.csv (poses at 1 kHz)"
for rate in 100 1000; do
  id=$(new_session cavity --rate $rate --frame-rate -1)
  sleep 1
  v drive "$id" --script "$root/scenes/clearing.csv" --pose-rate 1000 --json >"$work/drive.json"
  python3 - "$work/drive.json" "$rate" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); r, s = d["drive"], d["status"]
print(f"cavity {sys.argv[2]:>4} Hz: deadline misses {s['deadline_misses']} of {s['steps']} steps "
      f"({100.0 * s['deadline_misses'] / max(1, s['steps']):.3f} %); achieved {s['rate_hz']:.1f} Hz; "
      f"step p50 {s['step_cost_p50_us']:.0f} us p99 {s['step_cost_p99_us']:.0f} us, longest (wall, last 0.25 s) {s['step_wall_max_us']:.0f} us; "
      f"round trip p50 {r['round_trip_p50_us']:.0f} us p99 {r['round_trip_p99_us']:.0f} us; max |F| {r['max_force_n']:.2f} N")
PY
  v destroy "$id" >/dev/null
done

echo "== concurrent 100 Hz sessions of scenes/fall.toml (misses counted over 5 s after all started)"
ids=""
n=0
while [ $n -lt "$max_sessions" ]; do
  n=$((n + 1))
  id=$(new_session fall --frame-rate -1)
  ids="$ids $id"
  sleep 1.5
  v list --json >"$work/before.json"
  sleep 5
  v list --json >"$work/after.json"
  if ! python3 - "$work/before.json" "$work/after.json" "$n" <<'PY'
import json, sys
before = {s["session"]: s for s in json.load(open(sys.argv[1]))}
after = json.load(open(sys.argv[2]))
misses = sum(s["deadline_misses"] - before[s["session"]]["deadline_misses"] for s in after)
steps = sum(s["steps"] - before[s["session"]]["steps"] for s in after)
rates = [s["rate_hz"] for s in after]
p99 = max(s["step_cost_p99_us"] for s in after)
print(f"{sys.argv[3]:>2} sessions: {misses} misses in {steps} steps; achieved {min(rates):.1f}..{max(rates):.1f} Hz; worst step p99 {p99:.0f} us")
sys.exit(0 if misses == 0 and min(rates) > 95.0 else 1)
PY
  then
    echo "   -> $((n - 1)) sessions is the most this machine held at 100 Hz without misses"
    break
  fi
done
