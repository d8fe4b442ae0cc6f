#!/usr/bin/env bash
# A bounded libFuzzer run: TARGET CORPUS_DIR SECONDS [LIBFUZZER FLAGS...]. New inputs go to a scratch directory
# (the repo's corpus is only read); a crash, leak, timeout or sanitizer report fails it and
# leaves the input in the scratch directory, whose path is printed.
set -euo pipefail
target="$1" corpus="$2" seconds="${3:-5}"
shift $(($# < 3 ? $# : 3))
scratch="$(mktemp -d "${TMPDIR:-/tmp}/viscera-fuzz-$(basename "$target").XXXXXX")"
cd "$scratch"
if "$target" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -print_final_stats=1 "$@" \
    "$scratch" "$corpus" >"$scratch/log" 2>&1; then
  grep -E '^stat::(number_of_executed_units|new_units_added|peak_rss_mb)|cov:' "$scratch/log" | tail -4
  rm -rf "$scratch"
else
  tail -60 "$scratch/log"
  echo "fuzz: $(basename "$target") failed; inputs and log in $scratch" >&2
  exit 1
fi
