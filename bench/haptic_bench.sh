#!/bin/sh
# Haptic device loop benchmark (not a timed test; docs/server-benchmarks.md, "Haptics"): the real
# viscerad and `viscera haptic` with the simulated hand, over real UDP multicast in a private
# loopback-only network namespace. Prints:
#  1. device loop period error p50/p99/max and misses at 1 kHz (push scene, 1 kHz session),
#     as the machine is, then while a compiler loop runs beside it;
#  2. round trip pose -> force p50/p99 on scenes/cavity.toml at 100 Hz and 1 kHz sessions,
#     and the server's mechanics misses at 1 kHz (spin margin 200 us, then sleep only);
#  3. transparency: the press of tests/e2e rendered through 0, 10, 20, 50 and 100 ms of one-way
#     delay, against the zero-delay run (logs kept in OUT_DIR for tools/plot_transparency.py).
# Usage: bench/haptic_bench.sh [BUILD_DIR] [OUT_DIR]
set -eu
. "$(dirname "$0")/netns_server.sh"
build=${1:-$root/build}
out=${2:-$root/out/haptic_bench}
mkdir -p "$out"
echo "== $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg), commit $(git -C "$root" rev-parse --short HEAD)"
spin=${VISCERA_SPIN_US:--1}
start_server --server-id hbench --max-sessions 8 --spin-us "$spin"
cat >"$out/press.csv" <<'CSV'
t,tool,x,y,z,qw,qx,qy,qz,jaw
0,grasper,0,0,0.06,1,0,0,0,1
0.5,grasper,0,0,0.06,1,0,0,0,1
2.5,grasper,0,0,0.01,1,0,0,0,1
4.0,grasper,0,0,0.03,1,0,0,0,1
5.0,grasper,0,0,0.03,1,0,0,0,1
CSV
cat >"$out/summary.py" <<'PY'
import json, sys
d = json.load(sys.stdin)
if sys.argv[1] == "status":
    s = d
    print(f"   server: {s['rate_hz']:.1f} of {s['configured_rate_hz']:.0f} Hz, deadline misses {s['deadline_misses']} of {s['steps']} "
          f"({100.0 * s['deadline_misses'] / max(1, s['steps']):.2f} %), step p50 {s['step_cost_p50_us']:.0f} us p99 {s['step_cost_p99_us']:.0f} us, "
          f"jitter p99 {s['jitter_p99_us']:.0f} us")
    sys.exit(0)
d = d["haptic"]
print(f"{sys.argv[1]}: {d['achieved_rate_hz']:.1f} Hz, period error p50 {d['period_error_p50_us']:.1f} us p99 {d['period_error_p99_us']:.1f} us "
      f"max {d['period_error_max_us']:.0f} us, misses {d['deadline_misses']} of {d['periods']} ({100.0 * d['deadline_misses'] / max(1, d['periods']):.2f} %), "
      f"late wake-ups {d['late_wakeups']}; round trip p50 {d['round_trip_p50_us']:.0f} us p99 {d['round_trip_p99_us']:.0f} us; "
      f"model age p50 {d['model_age_p50_ms']:.1f} ms; peak {d['peak_force_n']:.2f} N")
PY
summary() { python3 "$out/summary.py" "$1"; }
push=$(new_session --scene-file "$root/tests/e2e/scenes/push.toml" --rate 1000 --frame-rate -1)

echo "== 1. device loop at 1 kHz (push scene, 1 kHz session, 5 s)"
v haptic "$push" --tool grasper --device sim --script "$out/press.csv" --json --quiet | summary "as is      "
# a build beside it: two compilers in a loop, as long as the run
( end=$(($(date +%s) + 7)); while [ "$(date +%s)" -lt "$end" ]; do
    c++ -O2 -std=c++20 -I"$root/src" -I/usr/include/eigen3 -c "$root/src/mechanics/forces.cc" -o /dev/null 2>/dev/null &
    c++ -O2 -std=c++20 -I"$root/src" -I/usr/include/eigen3 -c "$root/src/mechanics/model.cc" -o /dev/null 2>/dev/null; wait
  done ) &
builder=$!
sleep 1
v haptic "$push" --tool grasper --device sim --script "$out/press.csv" --json --quiet | summary "with build "
wait $builder
v destroy "$push" >/dev/null

echo "== 2. round trip on scenes/cavity.toml (the clearing gesture's first 3 s, left grasper)"
for rate in 100 1000; do
  id=$(new_session cavity --rate $rate --frame-rate -1)
  sleep 1
  v haptic "$id" --tool left --device sim --script "$root/scenes/clearing.csv" --seconds 3 --json --quiet | summary "cavity $rate Hz"
  v status "$id" --json | summary status
  v destroy "$id" >/dev/null
done

echo "== 3. transparency (push scene, 1 kHz session): the press through one-way delays"
push=$(new_session --scene-file "$root/tests/e2e/scenes/push.toml" --rate 1000 --frame-rate -1)
for d in 0 10 20 50 100; do
  v haptic "$push" --tool grasper --device sim --script "$out/press.csv" --delay-ms "$d" --log "$out/delay_$d.jsonl" --json --quiet \
    | summary "delay $d ms"
done
python3 - "$out" <<'PY'
import json, sys, bisect
out = sys.argv[1]
def load(d):
    return [json.loads(l) for l in open(f"{out}/delay_{d}.jsonl")]
ref = load(0)
rt = [r["t"] for r in ref]
peak = max(abs(r["force"][2]) for r in ref)
print(f"{'delay':>6} {'rms error (N)':>14} {'max error (N)':>14} {'rms / peak':>10} {'peak (N)':>9}")
for d in (0, 10, 20, 50, 100):
    run = load(d)
    errs = []
    for r in run:
        i = min(bisect.bisect_left(rt, r["t"]), len(ref) - 1)
        errs.append(r["force"][2] - ref[i]["force"][2])
    rms = (sum(e * e for e in errs) / len(errs)) ** 0.5
    print(f"{d:>4} ms {rms:>14.3f} {max(abs(e) for e in errs):>14.3f} {rms / peak:>10.3f} {max(abs(r['force'][2]) for r in run):>9.2f}")
PY
