#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) into build-fuzz/ and fuzzes each for
# SECONDS (default 60), starting from fuzz/corpus/<target> (new inputs go to
# build-fuzz/corpus/<target>, findings to build-fuzz/findings/<target>/). Fails when a target
# finds a crash, a sanitizer report, a leak, an input slower than 10 s or one using more than
# 2 GB. Turn every finding into a regression test: copy it into fuzz/regressions/<target>/,
# where the test suite replays it (ctest -L fuzz).
# The random seed is fixed (AREAMATCH_FUZZ_SEED, default 1); set it to 0 for a fresh seed each
# run when fuzzing for long. The targets run AREAMATCH_FUZZ_JOBS at a time (default: one per core).
#   scripts/fuzz.sh [SECONDS] [TARGET...]      targets: fuzz_image fuzz_yaml fuzz_segment fuzz_match
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_image fuzz_yaml fuzz_segment fuzz_match)

missing=()
for p in clang libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
scripts/setup.sh --deps-only

build=build-fuzz
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_COMPILER=clang++ -DAREAMATCH_BUILD_FUZZERS=ON \
      -DAREAMATCH_BUILD_TESTS=OFF -DAREAMATCH_BUILD_EXAMPLES=OFF -DAREAMATCH_BUILD_BENCHMARKS=OFF \
      -DAREAMATCH_BUILD_TOOLS=OFF -DAREAMATCH_INSTALL=OFF -DAREAMATCH_BUILD_PYTHON=OFF > /dev/null
cmake --build "$build" -j "$(nproc)" --target "${targets[@]}"

export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
# The targets run side by side, one per core (each still fuzzes for SECONDS); their reports
# follow in target order.
fuzz_one() {
  local t="$1"
  mkdir -p "$build/corpus/$t" "$build/findings/$t"
  if "$build/fuzz/$t" "$build/corpus/$t" "fuzz/corpus/$t" -max_total_time="$seconds" -seed="${AREAMATCH_FUZZ_SEED:-1}" -timeout=10 \
       -rss_limit_mb=2048 -max_len=8192 -artifact_prefix="$build/findings/$t/" -print_final_stats=1 \
       2> "$build/$t.log"; then
    echo 0 > "$build/$t.status"
  else
    echo 1 > "$build/$t.status"
  fi
}
jobs="${AREAMATCH_FUZZ_JOBS:-$(nproc)}"
running=0
for t in "${targets[@]}"; do
  rm -f "$build/$t.status"
  echo "== $t: ${seconds} s"
  fuzz_one "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait || true
status=0
for t in "${targets[@]}"; do
  if [ "$(cat "$build/$t.status" 2>/dev/null)" != 0 ]; then
    status=1
    echo "$t: FINDING (see $build/$t.log and $build/findings/$t/)"
    grep -E "ERROR|SUMMARY|Test unit written" "$build/$t.log" | head -5 || true
  else
    echo "$t: $(grep -E "stat::number_of_executed_units|cov:" "$build/$t.log" | tail -2 | tr '\n' ' ')"
  fi
done
exit $status
