#!/usr/bin/env bash
# The main job, end to end: installs what it needs, builds, and runs the default scene
# (scenes/fall.toml, the paper's 4 m / 250-point fall) offline, printing a summary and writing
# its trace to out/fall.jsonl.
# Usage: ./tools/demo.sh [SCENE.toml] [SECONDS]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/tools/setup.sh"
build="${VISCERA_BUILD_DIR:-$root/build}"
scene="${1:-$root/scenes/fall.toml}"
seconds="${2:-2}"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --parallel "$(nproc)" --target viscera-sim
mkdir -p "$root/out"
trace="$root/out/$(basename "$scene" .toml).jsonl"
echo "== viscera-sim $(basename "$scene"), ${seconds} s simulated"
"$build/tools/viscera-sim" "$scene" --duration "$seconds" --trace "$trace" --trace-every 5
echo "== trace: $trace ($(wc -l <"$trace") frames)"
