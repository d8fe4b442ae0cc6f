#!/usr/bin/env bash
# What a session costs the server, watched or not (a benchmark, not a test): viscerad's CPU
# time (user + system, /proc) over S seconds of one session, 100 Hz mechanics and 25 Hz frames
# at 640x480, in three states alternated ROUNDS times:
#   frameless  created with --frame-rate -1
#   unwatched  frames asked for, nobody renews the frame lease (a page drawing the session itself)
#   watched    frames asked for, `viscera frames` renews the lease and takes them
# Inside a loopback-only namespace. Prints cores per session = CPU s / wall s.
# Usage: bench/frame_lease_bench.sh [BUILD (build)] [SCENE (cavity)] [SKIN (convolution)] [S (20)] [ROUNDS (2)]
set -euo pipefail
. "$(dirname "$0")/netns_server.sh"
build=$(cd "${1:-$root/build}" && pwd) scene=${2:-cavity} skin=${3:-convolution} seconds=${4:-20} rounds=${5:-2}
cpu_s() {  # utime + stime of a process, in seconds
  awk -v hz="$(getconf CLK_TCK)" '{ print ($14 + $15) / hz }' "/proc/$1/stat"
}

start_server --server-id lease-bench --max-sessions 4 --adaptive-frames off  # the stream as asked
measure() {  # label create-args...
  local label=$1; shift
  local id
  id=$(new_session "$scene" --rate 100 --skin "$skin" --width 640 --height 480 "$@" --timeout 120)
  sleep 3  # past the first steps and frames
  local watcher=""
  if [[ $label == watched ]]; then
    v frames "$id" --out "$work/frames" --seconds $((seconds + 5)) >/dev/null 2>&1 &
    watcher=$!
    sleep 2
  fi
  local c0 t0 c1 t1
  c0=$(cpu_s "$server_pid"); t0=$(date +%s.%N)
  sleep "$seconds"
  c1=$(cpu_s "$server_pid"); t1=$(date +%s.%N)
  local frames
  frames=$(v status "$id" --json | python3 -c 'import json, sys; print(json.load(sys.stdin)["frames"]["sent"])')
  [[ -n $watcher ]] && { kill "$watcher" 2>/dev/null; wait "$watcher" 2>/dev/null || true; }
  v destroy "$id" >/dev/null
  rm -rf "$work/frames"
  python3 -c "import sys; c0, c1, t0, t1 = map(float, sys.argv[1:5]); \
print(f'$label: {(c1 - c0) / (t1 - t0):.3f} cores per session ($frames frames sent in all)')" "$c0" "$c1" "$t0" "$t1"
}
echo "== $scene, $skin skin, 100 Hz, 25 Hz 640x480 frames, $seconds s each, $rounds rounds, load $(cut -d' ' -f1 /proc/loadavg)"
for ((r = 1; r <= rounds; ++r)); do
  measure frameless --frame-rate -1
  measure unwatched --frame-rate 25
  measure watched --frame-rate 25
done
