#!/usr/bin/env bash
# Capacity sweep (docs/capacity.md): viscerad pinned to one core, tools/loadtest.py pinned to
# another, in a private loopback-only network namespace. For the fall and cavity scenes, at
# 100 Hz and 1 kHz (poses at the mechanics rate), without and with a 25 Hz frame stream (and,
# as `-skeleton`, with the 30 Hz skeleton stream a page that draws the session itself reads), it
# runs the load tester over growing session counts and writes, per configuration, the JSON
# reports and plots into OUT_DIR/<config>/, then the table OUT_DIR/capacity.md.
# Usage: tools/capacity.sh [OUT_DIR] [SECONDS_PER_RUN] [CONFIG...]
#   CONFIG: fall-100, fall-100-frames, fall-1000, ..., cavity-1000-frames (default: those 8),
#           cavity-100-skeleton, ...
# Environment: VISCERA_SERVER_CPU (1), VISCERA_CLIENT_CPU (0), VISCERA_BUILD_DIR (build),
#   VISCERA_SESSIONS (the session counts of every configuration, e.g. 1,2,3; default: sweep below),
#   VISCERA_TOOL_CENTER ("X Y Z", m: the centre of the tool's 1 cm circle; default 0 0 0.15, above
#   the pile; "0 0 0.07" presses into the cavity's pile and moves its bowel).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [[ "${VISCERA_IN_NETNS:-}" != 1 ]]; then
  exec "$root/tests/e2e/in_netns.sh" bash "${BASH_SOURCE[0]}" "$@"
fi
build="${VISCERA_BUILD_DIR:-$root/build}"
python="${VISCERA_VENV:-$root/.venv}/bin/python"
out="${1:-$root/out/capacity}"
seconds="${2:-10}"
shift $(( $# > 2 ? 2 : $# ))
configs=("$@")
((${#configs[@]})) || configs=(fall-100 fall-100-frames fall-1000 fall-1000-frames
                               cavity-100 cavity-100-frames cavity-1000 cavity-1000-frames)
server_cpu="${VISCERA_SERVER_CPU:-1}"
client_cpu="${VISCERA_CLIENT_CPU:-0}"
url='udpm://239.255.76.67:7667?ttl=0'
export PYTHONPATH="$root/python:$build/python${PYTHONPATH:+:$PYTHONPATH}"
mkdir -p "$out"

# Session counts per configuration: from one to a little past where the limits were crossed
# on a 2-vCPU machine shared with other work (docs/capacity.md); widen them on a quiet one.
sweep() {
  if [[ -n "${VISCERA_SESSIONS:-}" ]]; then echo "$VISCERA_SESSIONS"; return; fi
  case "$1" in
    fall-100 | cavity-100 | *-100-skeleton) echo 4,8,10,12,14,16 ;;
    fall-1000) echo 1,2,3 ;;
    *-100-frames) echo 1,2,3,4 ;;
    *-1000*) echo 1,2 ;;
  esac
}

server_pid=""
trap '[[ -n $server_pid ]] && kill -TERM $server_pid 2>/dev/null; wait' EXIT
for config in "${configs[@]}"; do
  IFS=- read -r scene rate frames <<<"$config"
  scene_args=(--scene "$scene")
  [[ $scene == fall ]] && scene_args=(--scene-file "$root/scenes/fall.toml"
                                      --scene-file "$root/bench/scenes/probe_tool.toml")
  center_args=()
  [[ -n "${VISCERA_TOOL_CENTER:-}" ]] && read -r -a center_args <<<"--center $VISCERA_TOOL_CENTER"
  frame_args=()
  [[ $frames == frames ]] && frame_args=(--frames --frame-rate 25)
  [[ $frames == skeleton ]] && frame_args=(--skeleton-rate 30)
  dir="$out/$config"
  mkdir -p "$dir"
  # --frame-lease 0: the load tester takes frames without renewing a frame lease; every
  # session streams as if watched. --max-creates-per-minute 0: a sweep creates more sessions a
  # minute than the default limit lets a client
  taskset -c "$server_cpu" "$build/server/viscerad" --server-id "capacity-$config" --max-sessions 64 \
    --max-rate 1000 --frame-lease 0 --max-creates-per-minute 0 --lcm-url "$url" --scene-dir "$root/scenes" 2>"$dir/viscerad.err" &
  server_pid=$!
  echo "== $config: sessions $(sweep "$config"), $seconds s each (viscerad on CPU $server_cpu, load tester on CPU $client_cpu)"
  status=0
  taskset -c "$client_cpu" "$python" "$root/tools/loadtest.py" --sessions "$(sweep "$config")" \
    --seconds "$seconds" --pose-rate "$rate" --session-rate "$rate" "${scene_args[@]}" \
    "${frame_args[@]}" "${center_args[@]}" --lcm-url "$url" --listen 3 --progress none --json "$dir/report.json" \
    --plots "$dir" >"$dir/summary.txt" 2>"$dir/loadtest.err" || status=$?
  # 1 (over capacity) is what a sweep is for; anything else is a failure worth seeing
  if (( status != 0 && status != 1 && status != 3 )); then
    echo "loadtest failed ($status):" >&2; tail -20 "$dir/loadtest.err" >&2
  fi
  kill -TERM "$server_pid"; wait "$server_pid" || true; server_pid=""
done
"$python" "$root/tools/capacity_table.py" "$out" | tee "$out/capacity.md"
