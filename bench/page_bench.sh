#!/usr/bin/env bash
# The viewer page drawing a live session itself (a benchmark, not a test): the real viscerad
# runs scenes/cavity.toml live (parametric skin, 640x480, 100 Hz, skeleton states at the
# session's rate) inside a loopback-only namespace (bench/netns_server.sh); `viscera view` serves
# the page and headless Chromium draws it in software WebGL2 (SwiftShader), once per variant of
# Chromium's flags. Prints one table row per variant: the frames the page drew per second over
# SECONDS, the skeleton states it received per second, the page's JavaScript per frame, a frame
# drawn and finished, Chromium's CPU by process and the load average (bench/page_bench.py).
# Usage: bench/page_bench.sh [BUILD (build)] [SECONDS (10)] [VARIANT...]
#   VARIANT: Chromium flags added to tests/e2e/devtools_pipe.py's ("!FLAG" drops one, "NAME:"
#   labels the row), e.g. 'angle:!--disable-gpu --use-angle=swiftshader --enable-unsafe-swiftshader'
set -euo pipefail
. "$(dirname "$0")/netns_server.sh"
build=$(cd "${1:-$root/build}" && pwd) seconds=${2:-10}
shift $(($# < 2 ? $# : 2))
echo "== $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the start, $seconds s per row"
start_server --server-id page-bench --adaptive-frames off
id=$(new_session cavity --skin parametric --width 640 --height 480 --timeout 120)
sleep 2  # past the first steps
python3 "$root/bench/page_bench.py" "$build/client/viscera" "$id" "$url" "$root/scenes" "$work" "$seconds" "$@"
v destroy "$id" >/dev/null
echo "== load average $(cut -d' ' -f1-3 /proc/loadavg) at the end"
