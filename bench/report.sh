#!/usr/bin/env bash
# Runs the benchmarks of docs/benchmarks.md and docs/server-benchmarks.md and prints each one's
# figures as the pages print them: a heading, the machine, commit and load average, then the
# Markdown table (Google Benchmark binaries, formatted by bench/report_table.py) or the program's
# own summary lines (bench_direct_coupling, bench_pacer and the scripts that drive viscerad).
#
# Usage: bench/report.sh [--list] [NAME...]      (no NAME: every benchmark, in the pages' order)
# Environment:
#   BUILD         the build tree (default: build), built with the bench targets
#   BENCH_ARGS    extra Google Benchmark flags, e.g. "--benchmark_min_time=0.05" for a quick look,
#                 "--benchmark_repetitions=3 --benchmark_report_aggregates_only=true" for medians
#   BENCH_FILTER  replaces the benchmark's own --benchmark_filter
#   BENCH_CPU     a core to pin Google Benchmark binaries to with taskset (default: none)
#   KEEP          a directory to keep the JSON reports in (default: a temporary one)
# e.g.  nice -n 19 bench/report.sh mesh-sdf
#       BENCH_ARGS=--benchmark_min_time=0.05 bench/report.sh mechanics
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
build=${BUILD:-build}
[[ $build = /* ]] || build=$root/$build

# name|kind|command: kind gb = a Google Benchmark binary (command: binary, then its own flags),
# text = a program or script that prints its own summary (command run as is, from the root).
benchmarks=(
  "cavity|gb|bench_contacts --benchmark_filter=CavityClearing"
  "fall|gb|bench_contacts --benchmark_filter=FallWhole/n:250/self:[01]\$|FallSettled/n:250/self:[01]\$|PaperCoil|FallWholeLimiterOnly"
  "mesentery|gb|bench_contacts --benchmark_filter=CavityMesentery"
  "direct-coupling|text|$build/bench/bench_direct_coupling"
  "mechanics|gb|bench_mechanics"
  "mesh-sdf|gb|bench_mesh_sdf --benchmark_enable_random_interleaving=true"
  "skins|gb|bench_skin"
  "render|gb|bench_render"
  "server|text|sh bench/server_bench.sh $build"
  "frames|text|sh bench/frames_bench.sh $build"
  "frame-lease|text|bash bench/frame_lease_bench.sh $build"
  "page|text|bash bench/page_bench.sh $build"
  "pacer|text|$build/bench/bench_pacer 10 1000 0 50 100 200 400"
  "haptic|text|sh bench/haptic_bench.sh $build"
)

list() {
  for b in "${benchmarks[@]}"; do
    IFS='|' read -r name kind cmd <<<"$b"
    [[ $kind = gb ]] && cmd="$build/bench/$cmd"
    printf '%-16s %s\n' "$name" "$cmd"
  done
}

header() {  # name
  local cpu
  cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
  echo "### $1"
  echo
  echo "$(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo '?')," \
    "$(nproc) CPUs ($cpu), load average $(cut -d' ' -f1-3 /proc/loadavg) at the start"
  echo
}

run() {  # name kind command
  local name=$1 kind=$2 cmd=$3
  header "$name"
  if [[ $kind = text ]]; then
    (cd "$root" && eval "$cmd")
    echo
    return
  fi
  local bin=${cmd%% *} flags=""
  [[ $cmd = *" "* ]] && flags=${cmd#* }
  [[ -x $build/bench/$bin ]] || { echo "report.sh: $build/bench/$bin not built (cmake --build $build --target $bin)" >&2; exit 1; }
  local args=()
  set -f
  for f in $flags; do
    [[ -n ${BENCH_FILTER:-} && $f = --benchmark_filter=* ]] && continue
    args+=("$f")
  done
  [[ -n ${BENCH_FILTER:-} ]] && args+=("--benchmark_filter=$BENCH_FILTER")
  set +f
  # shellcheck disable=SC2206
  args+=(${BENCH_ARGS:-})
  local pin=()
  [[ -n ${BENCH_CPU:-} ]] && pin=(taskset -c "$BENCH_CPU")
  local json=$out/$name.json
  "${pin[@]}" "$build/bench/$bin" "${args[@]}" --benchmark_format=json >"$json" 2>"$out/$name.err" ||
    { cat "$out/$name.err" >&2; exit 1; }
  python3 "$here/report_table.py" "$name" "$json"
  echo
  echo "(\`$bin ${args[*]}\`, CPU time)"
  echo
}

if [[ ${1:-} = --list ]]; then list; exit 0; fi
if [[ ${1:-} = -h || ${1:-} = --help ]]; then sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 0; fi
out=${KEEP:-$(mktemp -d)}
mkdir -p "$out"
[[ -n ${KEEP:-} ]] || trap 'rm -rf "$out"' EXIT
wanted=("$@")
for w in "${wanted[@]}"; do
  list | awk '{print $1}' | grep -qx -- "$w" || { echo "report.sh: no benchmark '$w' (bench/report.sh --list)" >&2; exit 2; }
done
for b in "${benchmarks[@]}"; do
  IFS='|' read -r name kind cmd <<<"$b"
  if ((${#wanted[@]} == 0)) || [[ " ${wanted[*]} " = *" $name "* ]]; then
    run "$name" "$kind" "$cmd"
  fi
done
