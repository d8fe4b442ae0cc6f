#!/bin/sh
# Frame-stream benchmark (not a timed test): the real viscerad and viscera over real UDP
# multicast inside a private loopback-only network namespace. Prints the figures that
# docs/server-benchmarks.md ("Frame streams") records:
#  1. frames per second delivered to a client, frames lost on the way, frames the server's
#     renderer dropped, frame age, per skin and rate, on the settled scenes/cavity.toml;
#  2. mechanics deadline misses at 100 Hz and 1 kHz without frames and while streaming;
#  3. loss with the kernel's default receive buffer against the 2 MB the client asks for,
#     with four sessions streaming at once.
# Usage: bench/frames_bench.sh [BUILD_DIR] [SECONDS] [SECTIONS]
#   SECTIONS: any of "client misses buffers" (default: all three)
set -eu
. "$(dirname "$0")/netns_server.sh"
build=${1:-$root/build}
seconds=${2:-10}
sections=${3:-client misses buffers}
wants() { case " $sections " in *" $1 "*) return 0 ;; esac; return 1; }
echo "== $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg), $seconds s per figure"
# the rates and sizes asked for, whatever the load (bench/frame_governor_bench.sh: the governor)
start_server --server-id bench --max-sessions 8 --max-frame-rate 120 --adaptive-frames off
session() { new_session "$@" --timeout 60; }
status() { v status "$1" --json >"$2"; }

report() {  # frames.json status-before.json status-after.json label
  python3 - "$@" <<'PY'
import json, sys
f = json.load(open(sys.argv[1])); b = json.load(open(sys.argv[2])); a = json.load(open(sys.argv[3]))
misses, steps = a["deadline_misses"] - b["deadline_misses"], a["steps"] - b["steps"]
fr = a["frames"]
print(f"{sys.argv[4]:<44} client {f['rate_hz']:5.1f} fps, lost {f['lost']} ({f['loss_percent']:.2f} %), "
      f"server dropped {f['server_dropped']}, age p50 {f['age_p50_ms']:.0f} ms p99 {f['age_p99_ms']:.0f} ms, "
      f"{f['mean_kb']:.0f} kB; skin {fr['skin_ms']:.1f} + render {fr['render_ms']:.1f} + encode {fr['encode_ms']:.2f} ms; "
      f"mechanics {a['rate_hz']:.0f}/{a['configured_rate_hz']:.0f} Hz, misses {misses} of {steps} steps")
PY
}

measure() {  # label create-arguments...
  label=$1; shift
  id=$(session "$@")
  sleep 2
  status "$id" "$work/before.json"
  if v frames "$id" --out "$work/frames" --seconds "$seconds" --json >"$work/frames.json"; then
    status "$id" "$work/after.json"
    report "$work/frames.json" "$work/before.json" "$work/after.json" "$label"
  else
    echo "$label: no frames"
  fi
  rm -rf "$work/frames"
  v destroy "$id" >/dev/null
}

misses() {  # label create-arguments...: deadline misses over SECONDS, no client
  label=$1; shift
  id=$(session "$@")
  sleep 2
  status "$id" "$work/before.json"
  sleep "$seconds"
  status "$id" "$work/after.json"
  python3 - "$work/before.json" "$work/after.json" "$label" <<'PY'
import json, sys
b = json.load(open(sys.argv[1])); a = json.load(open(sys.argv[2]))
m, s = a["deadline_misses"] - b["deadline_misses"], a["steps"] - b["steps"]
fr = a["frames"]
frames = f"{fr['rate_hz']:.1f} fps rendered" if fr["configured_rate_hz"] > 0 else "no frames"
print(f"{sys.argv[3]:<44} misses {m} of {s} steps ({100.0 * m / max(1, s):.3f} %), "
      f"step p99 {a['step_cost_p99_us']:.0f} us, {frames}")
PY
  v destroy "$id" >/dev/null
}

if wants client; then
echo "== frames delivered to one client (scenes/cavity.toml settled, mechanics 100 Hz)"
measure "parametric 640x480 25 Hz" cavity --frame-rate 25
measure "convolution 640x480 25 Hz" cavity --skin convolution --frame-rate 25
measure "hybrid 640x480 25 Hz" cavity --skin hybrid --frame-rate 25
measure "convolution 640x480 60 Hz" cavity --skin convolution --frame-rate 60
measure "parametric 1280x720 25 Hz" cavity --width 1280 --height 720 --frame-rate 25
measure "convolution 1280x720 25 Hz" cavity --skin convolution --width 1280 --height 720 --frame-rate 25
fi

if wants misses; then
echo "== mechanics deadline misses without and with frames (scenes/fall.toml, no client)"
for rate in 100 1000; do
  misses "$rate Hz, no frames" fall --rate $rate --frame-rate -1
  misses "$rate Hz, convolution 640x480 25 Hz" fall --rate $rate --skin convolution --frame-rate 25
  misses "$rate Hz, convolution 640x480 60 Hz" fall --rate $rate --skin convolution --frame-rate 60
done
fi

if wants buffers; then
echo "== four sessions streaming 640x480 parametric at 25 Hz; one client, receive buffer as given"
ids=""
for i in 1 2 3 4; do ids="$ids $(session fall --frame-rate 25)"; done
first=${ids# }; first=${first%% *}
sleep 2
for buf in 212992 2097152; do
  "$build/client/viscera" frames "$first" --out "$work/frames" --seconds "$seconds" --json \
    --lcm-url "$url&recv_buf_size=$buf" >"$work/frames.json"
  python3 - "$work/frames.json" "$buf" <<'PY'
import json, sys
f = json.load(open(sys.argv[1]))
print(f"recv_buf_size {int(sys.argv[2]):>8}: {f['frames']} frames, lost {f['lost']} ({f['loss_percent']:.2f} %), {f['rate_hz']:.1f} fps")
PY
  rm -rf "$work/frames"
done
for id in $ids; do v destroy "$id" >/dev/null; done
fi
