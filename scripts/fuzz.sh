#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) in the sanitizer build (build-sanitize/,
# the folder scripts/sanitize.sh tests in: same compiler and flags, so one build serves both) and
# fuzzes each for SECONDS (default 60), starting from fuzz/corpus/<target> (new inputs go to
# build-sanitize/fuzz-corpus/<target>, findings to build-sanitize/fuzz-findings/<target>/). Fails
# when a target finds a crash, a sanitizer report, a leak, an input slower than 10 s or one using
# more than 2 GB. Turn every finding into a regression test: copy it into
# fuzz/regressions/<target>/, where the test suite replays it (ctest -L fuzz).
# The random seed is fixed (AREAMATCH_FUZZ_SEED, default 1); set it to 0 for a fresh seed each
# run when fuzzing for long. The targets run AREAMATCH_FUZZ_JOBS at a time (default: one per core).
#   scripts/fuzz.sh [SECONDS] [TARGET...]      targets: fuzz_image fuzz_yaml fuzz_segment fuzz_match
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
all_targets=(fuzz_image fuzz_yaml fuzz_segment fuzz_match)
[ ${#targets[@]} -gt 0 ] || targets=("${all_targets[@]}")
for t in "${targets[@]}"; do
  case " ${all_targets[*]} " in
    *" $t "*) ;;
    *) echo "fuzz.sh: no target '$t' (targets: ${all_targets[*]})" >&2; exit 2 ;;
  esac
done

build="${AREAMATCH_SANITIZE_BUILD_DIR:-build-sanitize}"
AREAMATCH_BUILD_DIR="$build" scripts/setup.sh --sanitize --target areamatch_fuzz
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
# The targets run side by side, one per core (each still fuzzes for SECONDS); their reports
# follow in target order.
fuzz_one() {
  local t="$1"
  mkdir -p "$build/fuzz-corpus/$t" "$build/fuzz-findings/$t"
  if "$build/fuzz/$t" "$build/fuzz-corpus/$t" "fuzz/corpus/$t" -max_total_time="$seconds" -seed="${AREAMATCH_FUZZ_SEED:-1}" -timeout=10 \
       -rss_limit_mb=2048 -max_len=8192 -artifact_prefix="$build/fuzz-findings/$t/" -print_final_stats=1 \
       2> "$build/fuzz-$t.log"; then
    echo 0 > "$build/fuzz-$t.status"
  else
    echo 1 > "$build/fuzz-$t.status"
  fi
}
jobs="${AREAMATCH_FUZZ_JOBS:-$(nproc)}"
running=0
for t in "${targets[@]}"; do
  rm -f "$build/fuzz-$t.status"
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
  if [ "$(cat "$build/fuzz-$t.status" 2>/dev/null)" != 0 ]; then
    status=1
    echo "$t: FINDING (see $build/fuzz-$t.log and $build/fuzz-findings/$t/)"
    grep -E "ERROR|SUMMARY|Test unit written" "$build/fuzz-$t.log" | head -5 || true
  else
    echo "$t: $(grep -E "stat::number_of_executed_units|cov:" "$build/fuzz-$t.log" | tail -2 | tr '\n' ' ')"
  fi
done
exit $status
