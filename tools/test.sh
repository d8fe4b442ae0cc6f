#!/usr/bin/env bash
# Configures, builds and runs every viscera test with ctest. Installs what it needs first.
# Usage: ./tools/test.sh [extra ctest arguments for the main suite]
#
# First the form checks: tools/format.sh --check (every tracked C++ file as .clang-format has it)
# and tools/check_words.py (no tracked file speaks of how the work is done; the file lists the words).
# Then three parts, each timed (docs/reliability.md, "Sanitizers in CI", has the figures and why
# each part covers what it does), each built with -DVISCERA_WERROR=ON (a warning fails the build):
#   1. Release build (gcc), every test (unit, integration, end to end, the short soak).
#   2. clang with AddressSanitizer + UndefinedBehaviorSanitizer and libFuzzer instrumentation,
#      one build for both: the tests labelled asan (`ctest -L asan`: the unit tests of the code
#      that reads outside bytes: bus, protocol checks, client, scene and OBJ loaders, server limits
#      and security), then every fuzz target (`-L fuzz`) on its seed corpus and for
#      VISCERA_FUZZ_SECONDS (default 5) seconds.
#   3. gcc with ThreadSanitizer: the tests labelled tsan (`ctest -L tsan`), whose code runs several
#      threads (sessions, the session manager with its render threads, the bus, the MJPEG server).
# Each sanitizer build builds only what its labels run (the targets tests_<label>,
# tests/CMakeLists.txt). Parts 2 and 3 run by default (CI runs them); VISCERA_SANITIZERS=0 skips
# them while iterating. docs/reliability.md has each part's time in a whole fresh-clone CI run.
# ccache is used when installed (CCACHE_DIR as usual; nothing here sets it, so a fresh CI machine
# starts with an empty cache: docs/reliability.md has the cold figures).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/tools/setup.sh"
build="${VISCERA_BUILD_DIR:-$root/build}"
jobs="$(nproc)"
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
timings=()
timed() {  # NAME COMMAND...: runs it, keeps how long it took
  local name="$1" start=$SECONDS
  shift
  "$@"
  timings+=("$name: $((SECONDS - start)) s")
  echo "test.sh: $name took $((SECONDS - start)) s" >&2
}

# 0. form: every tracked C++ file as .clang-format has it (tools/format.sh fixes a difference)
timed "format check" "$root/tools/format.sh" --check
# ... and no words about how the work is done (the patterns' own examples first)
timed "word check" bash -c "'$root/tools/check_words.py' --self-test && '$root/tools/check_words.py'"

# 1. the main build and suite
timed "release build" bash -c "cmake -S '$root' -B '$build' -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DVISCERA_WERROR=ON ${launcher[*]} >/dev/null &&
  cmake --build '$build' --parallel $jobs"
timed "release tests" bash -c "cd '$build' && ctest --output-on-failure --timeout 600 -j$jobs $*"

if [[ "${VISCERA_SANITIZERS:-1}" != 0 ]]; then
  # Optimised a little (-O1) and with line tables only: sanitizer builds of Eigen-heavy code
  # are slow to compile, and the tests must stay fast enough to run.
  flags="-O1 -gline-tables-only"
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1"
  export LSAN_OPTIONS="suppressions=$root/tools/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
  export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$root/tools/tsan.supp"

  # 2. ASan + UBSan (clang), fuzz targets included
  asan="${build}-asan"
  timed "asan+ubsan build" bash -c "CC=clang CXX=clang++ cmake -S '$root' -B '$asan' -G Ninja -DCMAKE_BUILD_TYPE=None \
      '-DCMAKE_C_FLAGS=$flags' '-DCMAKE_CXX_FLAGS=$flags' -DVISCERA_SANITIZE=ON -DVISCERA_FUZZ=ON \
      -DVISCERA_WERROR=ON ${launcher[*]} >/dev/null &&
    cmake --build '$asan' --parallel $jobs --target tests_asan tests_fuzz"
  timed "asan+ubsan tests" bash -c "cd '$asan' && ctest --output-on-failure --timeout 900 -j$jobs -L asan"
  timed "fuzz (corpus + bounded runs)" bash -c "cd '$asan' && ctest --output-on-failure --timeout 900 -L fuzz"

  # 3. TSan (gcc): the threaded tests only, one at a time (each runs threads of its own)
  tsan="${build}-tsan"
  timed "tsan build" bash -c "cmake -S '$root' -B '$tsan' -G Ninja -DCMAKE_BUILD_TYPE=None \
      '-DCMAKE_C_FLAGS=-O1 -g1' '-DCMAKE_CXX_FLAGS=-O1 -g1' -DVISCERA_TSAN=ON -DVISCERA_WERROR=ON \
      ${launcher[*]} >/dev/null &&
    cmake --build '$tsan' --parallel $jobs --target tests_tsan"
  timed "tsan tests" bash -c "cd '$tsan' && ctest --output-on-failure --timeout 900 -L tsan"
fi
printf 'test.sh: %s\n' "${timings[@]}" >&2
