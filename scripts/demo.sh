#!/usr/bin/env bash
# Command 1 of the README: set up, build, and run the demo. Pictures go to ./areamatch-demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
"${AREAMATCH_BUILD_DIR:-build}/examples/demo" areamatch-demo
