#!/usr/bin/env bash
# Builds navaid with AddressSanitizer + UndefinedBehaviorSanitizer (clang, build-sanitize/) and
# runs the test suite under them; any finding fails its test (docs/robustness.md, "Sanitizers").
# Usage: scripts/test-sanitizers.sh [--ci] [extra ctest arguments]
#   --ci  the part .ci/run runs within its time limit: the core and io rooms' tests (every reader
#         of outside input) and a 10 s smoke run of their fuzz harnesses. Without it: everything.
set -euo pipefail
cd "$(dirname "$0")/.."
CI_SUBSET=0
if [ "${1:-}" = "--ci" ]; then CI_SUBSET=1; shift; fi
BUILD=${NAVAID_SANITIZE_BUILD:-build-sanitize}
IO_FUZZERS=(fuzz_nmea_capture fuzz_navaid_recording fuzz_euroc fuzz_tum_rgbd fuzz_tum_trajectory fuzz_kalibr fuzz_ros_bag
  fuzz_occupancy_map)
start=$(date +%s)
bash scripts/install-deps.sh --sanitizers
if [ "$CI_SUBSET" = 1 ]; then
  bash scripts/sanitize-build.sh navaid_core_tests navaid_io_tests "${IO_FUZZERS[@]}"
else
  bash scripts/sanitize-build.sh
fi
echo "test-sanitizers: built in $(( $(date +%s) - start )) s"

SUPP="$PWD/tests/sanitizers"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:suppressions=$SUPP/asan.supp"
export LSAN_OPTIONS="suppressions=$SUPP/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$SUPP/ubsan.supp"
test_start=$(date +%s)
if [ "$CI_SUBSET" = 1 ]; then
  ctest --test-dir "$BUILD" --output-on-failure -j2 --timeout 1800 -L '^(core|io)$' "$@"
  unset ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS
  NAVAID_FUZZ_SIMULATED_SEEDS=0 bash scripts/fuzz.sh 10 "${IO_FUZZERS[@]}"
else
  # The packaging test builds an outside project against the installed (sanitized) libraries.
  ctest --test-dir "$BUILD" --output-on-failure -j2 --timeout 1800 -E '^downstream_' "$@"
fi
echo "test-sanitizers: tests in $(( $(date +%s) - test_start )) s, all in $(( $(date +%s) - start )) s"
