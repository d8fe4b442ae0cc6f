#!/usr/bin/env bash
# Configures, builds and runs every viscera test with ctest. Installs what it needs first.
# Usage: ./tools/test.sh [extra ctest arguments for the main suite]
#
# First the form checks: tools/format.sh --check (every tracked C++ file as .clang-format has it)
# and tools/check_words.py (no tracked file speaks of how the work is done; the file lists the words).
# Then three parts, each timed (docs/reliability.md, "Sanitizers in CI", has the figures and why
# each part covers what it does):
#   1. Release build (gcc), every test (unit, integration, end to end, the short soak).
#   2. clang with AddressSanitizer + UndefinedBehaviorSanitizer and libFuzzer instrumentation,
#      one build for both: the unit tests of the code that reads outside bytes (bus, protocol
#      checks, client, scene and OBJ loaders, server limits and security), then every fuzz
#      target on its seed corpus and for VISCERA_FUZZ_SECONDS (default 5) seconds.
#   3. gcc with ThreadSanitizer: the tests whose code runs several threads (sessions, the
#      session manager with its render threads, the bus, the MJPEG server).
# Parts 2 and 3 run by default (CI runs them); VISCERA_SANITIZERS=0 skips them while iterating.
# docs/reliability.md has each part's time in a whole fresh-clone CI run.
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
timed "release build" bash -c "cmake -S '$root' -B '$build' -G Ninja -DCMAKE_BUILD_TYPE=Release ${launcher[*]} >/dev/null &&
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
  run_each() {  # DIR TEST...: runs each test binary of DIR/tests, stops at the first failure
    local dir="$1" t
    shift
    for t in "$@"; do
      (cd "$dir/tests" && "./$t" --gtest_brief=1) || { echo "test.sh: $t failed under a sanitizer" >&2; return 1; }
    done
  }

  # 2. ASan + UBSan (clang), fuzz targets included
  asan="${build}-asan"
  fuzz_targets=(fuzz_server_messages fuzz_client_messages fuzz_scene_toml fuzz_obj_loader
                fuzz_record_reader fuzz_http_request)
  asan_tests=(test_common_rate_window_test test_common_pacer_test test_bus_lcm_bus_test
              test_bus_message_auth_test test_bus_replay_guard_test test_bus_wire_counts_test
              test_scene_scene_test test_collision_obstacle_test test_collision_triangle_bvh_test
              test_session_inbox_test test_server_security_test test_server_heartbeat_source_test
              test_server_frame_schedule_test test_client_frame_receiver_test test_client_http_request_test
              test_client_token_store_test test_client_server_directory_test
              test_mechanics_force_lanes_test test_mechanics_contact_window_test
              test_mechanics_block_band_test test_collision_pair_separation_test
              test_mechanics_linearization_guard_test test_scene_toml_bounds_test
              test_scene_scene_limits_test test_session_session_scene_test test_client_jpeg_header_test
              test_session_outbox_test)
  timed "asan+ubsan build" bash -c "CC=clang CXX=clang++ cmake -S '$root' -B '$asan' -G Ninja -DCMAKE_BUILD_TYPE=None \
      '-DCMAKE_C_FLAGS=$flags' '-DCMAKE_CXX_FLAGS=$flags' -DVISCERA_SANITIZE=ON -DVISCERA_FUZZ=ON ${launcher[*]} >/dev/null &&
    cmake --build '$asan' --parallel $jobs --target ${fuzz_targets[*]} ${asan_tests[*]}"
  timed "asan+ubsan tests" run_each "$asan" "${asan_tests[@]}"
  timed "fuzz (corpus + bounded runs)" bash -c "cd '$asan' && ctest --output-on-failure --timeout 900 -L fuzz"

  # 3. TSan (gcc): the threaded tests only
  tsan="${build}-tsan"
  tsan_tests=(test_session_session_test test_session_snapshot_test test_server_session_manager_test
              test_server_security_test test_bus_lcm_bus_test test_client_mjpeg_server_test)
  timed "tsan build" bash -c "cmake -S '$root' -B '$tsan' -G Ninja -DCMAKE_BUILD_TYPE=None \
      '-DCMAKE_C_FLAGS=-O1 -g1' '-DCMAKE_CXX_FLAGS=-O1 -g1' -DVISCERA_TSAN=ON ${launcher[*]} >/dev/null &&
    cmake --build '$tsan' --parallel $jobs --target ${tsan_tests[*]}"
  timed "tsan tests" run_each "$tsan" "${tsan_tests[@]}"
fi
printf 'test.sh: %s\n' "${timings[@]}" >&2
