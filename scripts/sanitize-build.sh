#!/usr/bin/env bash
# Configures and builds the sanitizer tree (docs/robustness.md): clang, AddressSanitizer +
# UndefinedBehaviorSanitizer on all of navaid, libFuzzer coverage on the parsing rooms, the fuzz
# harnesses, no benchmarks. Used by scripts/test-sanitizers.sh and scripts/fuzz.sh.
# Usage: sanitize-build.sh [TARGET...]   (default: everything)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${NAVAID_SANITIZE_BUILD:-build-sanitize}
# -O1 keeps the sanitizers' stack traces close to the source at a fraction of -O0's run time.
CC=clang CXX=clang++ cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Sanitize \
  -DCMAKE_C_FLAGS_SANITIZE="-O1 -gline-tables-only" -DCMAKE_CXX_FLAGS_SANITIZE="-O1 -gline-tables-only" \
  -DNAVAID_SANITIZE=ON -DNAVAID_BUILD_FUZZERS=ON -DNAVAID_BUILD_BENCHMARKS=OFF -DNAVAID_WERROR=OFF >/dev/null
if [ $# -gt 0 ]; then
  cmake --build "$BUILD" -j2 --target "$@"
else
  cmake --build "$BUILD" -j2
fi
