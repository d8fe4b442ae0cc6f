#!/usr/bin/env bash
# The frame governor under overload (a benchmark, not a test): one session of scenes/cavity.toml,
# 100 Hz mechanics, 25 Hz 640x480 frames watched by `viscera frames`, with LOAD busy loops beside
# viscerad (each ended by `timeout` with its run), viscerad --adaptive-frames on and off alternated
# ROUNDS times. Per run, over S seconds after a 5 s start: the mechanics' deadline misses and
# longest step (wall time), the frames a client received per second, and the frame rate and size
# the stream was at in the end (the governor's level; the configured ones when off).
# Inside a loopback-only namespace.
# Usage: bench/frame_governor_bench.sh [BUILD (build)] [SKIN (parametric)] [S (20)] [LOAD (2)] [ROUNDS (1)]
set -euo pipefail
. "$(dirname "$0")/netns_server.sh"
build=$(cd "${1:-$root/build}" && pwd) skin=${2:-parametric} seconds=${3:-20} load=${4:-2}
rounds=${5:-1}

echo "== $(nproc) cores ($(lscpu | sed -n 's/^Model name: *//p')), load average" \
  "$(cut -d' ' -f1-3 /proc/loadavg); $skin, $load busy loops, $seconds s per run"
run() {  # on|off
  start_server --server-id "governor-$1" --max-sessions 2 --adaptive-frames "$1"
  local id
  id=$(new_session cavity --skin "$skin" --rate 100 --width 640 --height 480 --frame-rate 25 \
    --timeout 120)
  local busy=()
  for _ in $(seq "$load"); do
    timeout $((seconds + 15)) sh -c 'while :; do :; done' &
    busy+=($!)
  done
  v frames "$id" --out "$work/warm" --seconds 5 >/dev/null  # the governor finds its level
  v status "$id" --json >"$work/before.json"
  v frames "$id" --out "$work/frames" --seconds "$seconds" --json >"$work/frames.json"
  v status "$id" --json >"$work/after.json"
  if ((${#busy[@]} > 0)); then  # a bare `wait` would wait for viscerad too
    kill "${busy[@]}" 2>/dev/null || true
    wait "${busy[@]}" 2>/dev/null || true
  fi
  python3 - "$work/before.json" "$work/after.json" "$work/frames.json" "$1" <<'PY'
import json, sys
b, a, f = (json.load(open(p)) for p in sys.argv[1:4])
m, s = a["deadline_misses"] - b["deadline_misses"], a["steps"] - b["steps"]
fr = a["frames"]
print(f"adaptive {sys.argv[4]:3s}: misses {m} of {s} steps ({100.0 * m / max(1, s):.2f} %), "
      f"longest step {a['step_wall_max_us'] / 1e3:.1f} ms; client {f['rate_hz']:.1f} fps, "
      f"stream at {fr['configured_rate_hz']:.0f} Hz {fr['size']}, frame skin {fr['skin_ms']:.1f} + "
      f"render {fr['render_ms']:.1f} + encode {fr['encode_ms']:.1f} ms")
PY
  v destroy "$id" >/dev/null
  stop_server
  rm -rf "$work/warm" "$work/frames"
}
for _ in $(seq "$rounds"); do
  run on
  run off
done
