#!/usr/bin/env bash
# Builds navaid with its tests and benchmarks and runs the whole test suite.
# Installs what it needs from Debian packages first (root or sudo).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2
ctest --test-dir build --output-on-failure -j2 --timeout 900
