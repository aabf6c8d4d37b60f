#!/usr/bin/env bash
# Command 1 of the README: set up, build the demo (only it: a few minutes on 2 cores), and run it.
# Pictures go to ./areamatch-demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --no-python --target demo
"${AREAMATCH_BUILD_DIR:-build}/examples/demo" areamatch-demo
