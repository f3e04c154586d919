#!/usr/bin/env bash
# Runs the whole test suite (GoogleTest through CTest) on the Release build made by setup.sh.
#   bash scripts/test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${DLOAM_BUILD_DIR:-build}
if [[ ! -f "$BUILD_DIR/CMakeCache.txt" ]]; then
  DLOAM_SKIP_DEMO=1 bash scripts/setup.sh
fi
cmake --build "$BUILD_DIR" -j"$(nproc)"
ctest --test-dir "$BUILD_DIR" --output-on-failure -j"$(nproc)" "$@"
