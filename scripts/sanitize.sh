#!/usr/bin/env bash
# Builds the tests and the program with clang's AddressSanitizer + UndefinedBehaviorSanitizer
# (Debug, -O1, frame pointers kept, every UB report fatal) into build-sanitize/ and runs the test suite
# there, including the replay of the fuzz corpus. Any sanitizer report fails the run. The
# packaging, benchmark and compile-fail tests and the examples are left to scripts/test.sh: they
# test the install, speed, the compiler's messages and the README, not memory safety.
#   scripts/sanitize.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${AREAMATCH_SANITIZE_BUILD_DIR:-build-sanitize}"
AREAMATCH_BUILD_DIR="$build_dir" scripts/setup.sh --sanitize
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
# Sanitized code runs several times slower: the long test loops run a few iterations
# (AREAMATCH_QUICK_TESTS), and the tests on the full-size real maps are left to the Release run.
export AREAMATCH_QUICK_TESTS=1
cd "$build_dir"
ctest --output-on-failure -j "$(nproc)" -LE "packaging|benchmark|shared|compile_fail" --timeout 1500
