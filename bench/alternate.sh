#!/bin/bash
# Two benchmark binaries (a reference and a change) run in turn, ROUNDS times, so that both
# see the same load on a shared machine; prints per row the medians of COUNTER (us_per_step by
# default), the ratio change / reference of each round and its median, and p99 where the row
# has one.
# Usage: bash bench/alternate.sh REF_BIN NEW_BIN ROUNDS FILTER OUT_DIR [COUNTER]
#   e.g. bash bench/alternate.sh /tmp/ref/bench_contacts build/bench/bench_contacts 5 \
#          'CavityClearing|FallWhole/n:250/self:1$|PaperCoil' /tmp/alternate
#        bash bench/alternate.sh /tmp/ref/bench_render build/bench/bench_render 5 \
#          'BM_Frame/0/640/480/0/1/1/' /tmp/alternate cpu_ms
set -euo pipefail
ref=$1 new=$2 rounds=$3 filter=$4 out=$5 counter=${6:-us_per_step}
mkdir -p "$out"
for r in $(seq 1 "$rounds"); do
  "$ref" --benchmark_filter="$filter" --benchmark_format=json > "$out/ref_$r.json" 2>/dev/null
  "$new" --benchmark_filter="$filter" --benchmark_format=json > "$out/new_$r.json" 2>/dev/null
done
python3 - "$out" "$rounds" "$counter" <<'PY'
import json, statistics, sys
out, rounds, counter = sys.argv[1], int(sys.argv[2]), sys.argv[3]
def rows(kind, r):
    return {b["name"]: b for b in json.load(open(f"{out}/{kind}_{r}.json"))["benchmarks"]}
ref = [rows("ref", r) for r in range(1, rounds + 1)]
new = [rows("new", r) for r in range(1, rounds + 1)]
for name in ref[0]:
    a = [x[name][counter] for x in ref]
    b = [x[name][counter] for x in new]
    ratios = [bb / aa for aa, bb in zip(a, b)]
    line = (f"{name:45s} ref {statistics.median(a):8.1f} new {statistics.median(b):8.1f} "
            f"ratio {statistics.median(ratios):.3f} [{' '.join(f'{x:.3f}' for x in ratios)}]")
    if "p99_us" in ref[0][name]:
        line += (f" p99 {statistics.median(x[name]['p99_us'] for x in ref):.0f} -> "
                 f"{statistics.median(x[name]['p99_us'] for x in new):.0f}")
    print(line)
PY
