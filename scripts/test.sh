#!/usr/bin/env bash
# Command 2 of the README: set up, build, and run the whole test suite through ctest.
# Tests that need ../shared (the real maps) report "skipped" when it is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cd "${AREAMATCH_BUILD_DIR:-build}"
ctest --output-on-failure -j "$(nproc)"
