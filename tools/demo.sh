#!/usr/bin/env bash
# The main job, end to end: installs what it needs, builds, starts viscerad in the
# background, creates a session on the training scene (docs/training.md), drives the clearing
# gesture with the viscera client while it prints the hidden lesion's exposure as the gesture
# uncovers it, prints the force and timing figures and the assessment report, records the session's frame stream (convolution skin,
# OSMesa, JPEG over LCM; 10 Hz of the default skin on fewer than 4 cores) into out/demo/clearing.mp4 and saves a few frames in out/demo/frames,
# runs the haptic device bridge (`viscera haptic`, a simulated hand on the right grasper at 1 kHz)
# for a few seconds and prints its summary, destroys the session and stops the server.
# Everything runs in a private network namespace holding only loopback (nothing leaves
# this machine; VISCERA_DEMO_NETNS=0 uses the host's network instead, ttl=0).
# The session's record is kept in out/records/.
# Usage: ./tools/demo.sh [SCENE] [POSE_RATE_HZ]
#   SCENE: a scene of scenes/ with the clearing gesture's "right" grasper (default: cavity,
#   the 190-point intestine fanned on its mesentery in the abdominal cavity, with the lesion
#   that scenes/clearing.csv exposes); bowel_run: running the bowel hand over hand
#   (docs/training.md), its three scripted runs offline with viscera-sim, their reports side by
#   side and frames of the rough run with the damage colour in out/demo/bowel_run
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VISCERA_BUILD_DIR:-$root/build}"
scene="${1:-cavity}"
pose_rate="${2:-1000}"

if [ "$scene" = bowel_run ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" --parallel "$(nproc)" --target viscera-sim
  out="$root/out/demo/bowel_run"
  rm -rf "$out" && mkdir -p "$out"
  for run in expert rough careless; do
    script="$root/scenes/bowel_run_$run.csv"
    # the script's last row, and 2 s for the grasps its graspers may reach for again
    duration=$(tail -1 "$script" | cut -d, -f1 | awk '{ print $1 + 2 }')
    echo "== running the bowel: the $run run ($duration s simulated, 100 Hz)"
    # the laparoscope follows the work; the rough run's frames look down on the whole fan
    view=(--camera-script "$root/scenes/bowel_run_${run}_camera.csv")
    [ "$run" = rough ] && view=(--render "$out/frames_$run" --render-every 500 --camera 0.0 -0.05 0.42 0.0 0.0 0.08)
    "$build/tools/viscera-sim" "$root/scenes/bowel_run.toml" --duration "$duration" \
      --tool-script "$script" --report "$out/$run.json" "${view[@]}" | sed -n '/^running/,$p'
  done
  echo "== reports (JSON) and frames of the rough run (damage in blue-violet) in $out"
  exit 0
fi

if [ "${VISCERA_IN_NETNS:-}" != 1 ]; then
  "$root/tools/setup.sh"
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" --parallel "$(nproc)" --target viscerad viscera_cli
  if [ "${VISCERA_DEMO_NETNS:-1}" = 1 ]; then
    if [ "$(id -u)" = 0 ]; then
      # as root, a plain network namespace: unlike the user namespace of the tests (unshare
      # -rn), it keeps the right to SCHED_FIFO, so the server and the device loop can use it
      exec unshare -n env VISCERA_IN_NETNS=1 VISCERA_BUILD_DIR="$build" \
        sh "$root/tests/e2e/in_netns.sh" bash "$0" "$scene" "$pose_rate"
    fi
    exec "$root/tests/e2e/in_netns.sh" env VISCERA_IN_NETNS=1 VISCERA_BUILD_DIR="$build" \
      bash "$0" "$scene" "$pose_rate"
  fi
fi

# The best this machine allows: SCHED_FIFO for the mechanics, I/O and device loop threads when
# the kernel grants it, and frames it can sustain beside them. Where it cannot, say plainly
# what the figures below then measure.
cores=$(nproc)
realtime=()
haptic_realtime=()
if chrt -f 10 true 2>/dev/null; then
  realtime=(--realtime 80)
  haptic_realtime=(--realtime 90)
  echo "== SCHED_FIFO granted: the server's mechanics and I/O threads at 80, the device loop at 90"
else
  echo "== SCHED_FIFO not granted here (not root, or a user namespace): the server, its renderer and"
  echo "   this client share $cores core(s) at normal priority, so a device loop below 1000 Hz and"
  echo "   deadline misses below measure this machine's contention, not the system (as root,"
  echo "   ./tools/demo.sh runs in a plain network namespace, where SCHED_FIFO is allowed)"
fi
if [ "$cores" -ge 4 ]; then
  frames=(--skin convolution --frame-rate 25)
else
  # a 640x480 convolution frame costs ~45 ms of CPU: 25 of them a second take more than one of
  # two cores; the default skin at 10 Hz leaves the mechanics and the device loop their share
  frames=(--frame-rate 10)
  echo "== $cores core(s): frames of the default skin at 10 Hz (--skin convolution at 25 Hz wants 4 cores)"
fi

url='udpm://239.255.76.67:7667?ttl=0'
records="$root/out/records"
demo="$root/out/demo"
mkdir -p "$records"
rm -rf "$demo" && mkdir -p "$demo"
export VISCERA_SESSIONS="$root/out/sessions.json"
viscera() { "$build/client/viscera" "$@" --lcm-url "$url"; }

echo "== viscerad (background; records in out/records)"
"$build/server/viscerad" --server-id demo --lcm-url "$url" --scene-dir "$root/scenes" \
  --log-dir "$records" "${realtime[@]}" 2>"$root/out/viscerad.log" &
server=$!
trap 'kill -TERM $server 2>/dev/null || true; wait $server 2>/dev/null || true' EXIT
viscera servers --timeout 1.2

echo "== create a session on scenes/$scene.toml"
id=$(viscera create "$scene" "${frames[@]}" --json | python3 -c 'import json, sys; print(json.load(sys.stdin)["session"])')
echo "session $id"
sleep 1
viscera status "$id"

echo "== drive the clearing gesture (poses at $pose_rate Hz), recording the frames"
# the binary itself in the background, not the function: its subshell would take the signal
"$build/client/viscera" record "$id" --out "$demo/clearing.mp4" --lcm-url "$url" >"$demo/record.txt" &
recorder=$!
# the lesion's exposure from the session's status messages, printed as it changes
"$root/.venv/bin/python" "$root/tools/watch_exposure.py" "$id" --lcm-url "$url" &
watcher=$!
viscera drive "$id" --gesture clearing --pose-rate "$pose_rate"
kill -TERM $watcher  # (drive ends after its settling time: the last evaluations are in)
wait $watcher 2>/dev/null || true
kill -TERM $recorder  # ends it cleanly: the video gets its trailer (background jobs ignore SIGINT)
wait $recorder
cat "$demo/record.txt"
echo "== a few frames of the scene after the gesture"
viscera frames "$id" --out "$demo/frames" --count 5
viscera status "$id"
echo "== the assessment so far: handling metrics and the lesion's exposure (docs/assessment.md)"
viscera report "$id"

echo "== the haptic device bridge: a simulated hand follows the gesture's start at 1 kHz and feels the force"
viscera haptic "$id" --tool right --device sim --script "$root/scenes/clearing.csv" --seconds 4 --quiet \
  --log "$demo/haptic.jsonl" "${haptic_realtime[@]}"
echo "   (one line per 1 ms device period in $demo/haptic.jsonl; the verdict line says whether the"
echo "   loop held 1 kHz on this machine, and what to try if not)"

echo "== destroy the session, stop the server"
# the session's last status carries its final assessment: `report --final` waits for it
"$build/client/viscera" report "$id" --final --lcm-url "$url" >"$demo/report.txt" &
final=$!
sleep 0.5  # (report --final subscribes before the session ends; nothing below depends on it)
viscera destroy "$id"
wait $final
kill -TERM $server
wait $server
trap - EXIT
tail -n 2 "$root/out/viscerad.log"
echo "== record: $(ls -1 "$records"/session-"$id".lcmlog) (lcm-logplayer reads it)"
echo "== the final assessment report (viscera report $id --final; docs/training.md)"
sed 's/^/   /' "$demo/report.txt"
echo "== assessment JSON: $(ls -1 "$records"/session-"$id".assessment.json) (written by viscerad when the session ended)"
echo "== video: $demo/clearing.mp4, frames: $demo/frames/"
