#!/usr/bin/env bash
# Configures, builds and runs every viscera test with ctest. Installs what it needs first.
# Usage: ./tools/test.sh [extra ctest arguments for the main suite]
#
# Three parts, each timed (docs/reliability.md has the figures):
#   1. Release build (gcc), every test (unit, integration, end to end, the short soak).
#   2. clang with AddressSanitizer + UndefinedBehaviorSanitizer and libFuzzer instrumentation:
#      the unit, integration and end-to-end tests again, then every fuzz target on its seed
#      corpus and for VISCERA_FUZZ_SECONDS (default 5) seconds.
#   3. gcc with ThreadSanitizer: the tests whose code runs several threads.
# Parts 2 and 3 run with VISCERA_SANITIZERS=1. They are off by default until one full run has
# been measured green within CI's time budget (docs/reliability.md, "Sanitizers in CI": the
# builds have not yet completed on the shared machine).
# ccache is used when installed (CCACHE_DIR as usual).
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

# 1. the main build and suite
timed "release build" bash -c "cmake -S '$root' -B '$build' -G Ninja -DCMAKE_BUILD_TYPE=Release ${launcher[*]} >/dev/null &&
  cmake --build '$build' --parallel $jobs"
timed "release tests" bash -c "cd '$build' && ctest --output-on-failure --timeout 600 -j$jobs $*"

if [[ "${VISCERA_SANITIZERS:-0}" != 0 ]]; then
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
      '-DCMAKE_C_FLAGS=$flags' '-DCMAKE_CXX_FLAGS=$flags' -DVISCERA_SANITIZE=ON -DVISCERA_FUZZ=ON ${launcher[*]} >/dev/null &&
    cmake --build '$asan' --parallel $jobs"
  # the soak's memory bound is for a release server (ASan keeps freed memory in quarantine)
  timed "asan+ubsan tests" bash -c "cd '$asan' && ctest --output-on-failure --timeout 900 -j$jobs -LE 'soak|fuzz'"
  timed "fuzz (corpus + bounded runs)" bash -c "cd '$asan' && ctest --output-on-failure --timeout 900 -L fuzz"

  # 3. TSan (gcc): the threaded tests only (sessions, the server, the bus, the viewer server)
  tsan="${build}-tsan"
  tsan_tests=(test_session_session_test test_session_snapshot_test test_server_session_manager_test
              test_server_security_test test_bus_lcm_bus_test test_client_mjpeg_server_test)
  timed "tsan build" bash -c "cmake -S '$root' -B '$tsan' -G Ninja -DCMAKE_BUILD_TYPE=None \
      '-DCMAKE_C_FLAGS=-O1 -g1' '-DCMAKE_CXX_FLAGS=-O1 -g1' -DVISCERA_TSAN=ON ${launcher[*]} >/dev/null &&
    cmake --build '$tsan' --parallel $jobs --target ${tsan_tests[*]}"
  tsan_run() {
    local t
    for t in "${tsan_tests[@]}"; do
      (cd "$tsan/tests" && "./$t" --gtest_brief=1) || return 1
    done
  }
  timed "tsan tests" tsan_run
fi
printf 'test.sh: %s\n' "${timings[@]}" >&2
