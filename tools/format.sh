#!/usr/bin/env bash
# Formats every tracked C++ file with clang-format and the repository's .clang-format.
# Usage: tools/format.sh          rewrites the files in place
#        tools/format.sh --check  changes nothing; lists the files that differ and exits 1 if any
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
mapfile -t files < <(git ls-files '*.cc' '*.h')
if [[ "${1:-}" == --check ]]; then
  differ=()
  for f in "${files[@]}"; do
    clang-format "$f" | cmp -s - "$f" || differ+=("$f")
  done
  if ((${#differ[@]} > 0)); then
    printf 'format: %s differs from .clang-format (tools/format.sh fixes it)\n' "${differ[@]}" >&2
    exit 1
  fi
  echo "format: ${#files[@]} C++ files match .clang-format" >&2
else
  clang-format -i "${files[@]}"
fi
