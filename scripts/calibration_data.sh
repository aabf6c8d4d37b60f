#!/usr/bin/env bash
# Makes the rows the accept/reject decision is calibrated and cross-validated on
# (docs/evaluation.md, "Leave-one-building-out cross-validation"): every pair of ../shared and of
# generated sets, the pairs of maps of different buildings in both directions, one
# `areamatch eval` per set, each writing OUT/<set>/results.csv. Then
#   build/tools/areamatch calibrate OUT/*/results.csv [--choose-rule --max-false-accept F]
#     [--simulated OUT/simulated/set/eval/results.csv,OUT/simulated/onto_other_plans/results.csv]
# Runs JOBS evaluations at a time (default: the number of cores). About an hour on 2 cores.
#   scripts/calibration_data.sh OUT [AREAMATCH_BINARY] [JOBS]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:?usage: scripts/calibration_data.sh OUT [AREAMATCH_BINARY] [JOBS]}"
bin="$(realpath "${2:-$here/build/tools/areamatch}")"
jobs="${3:-$(nproc)}"
shared="$(realpath "$here/../shared")"
python="python3"; [ -x /usr/bin/python3 ] && python=/usr/bin/python3
mkdir -p "$out/sets" "$out/manifests"
out="$(realpath "$out")"

# Generated buildings: A clean and fully explored, B mirrored, noisier and 70 % explored, C 40 %
# explored; hand-held style: 50 pairs, and 12 more buildings for pairs of different buildings.
gen() { [ -f "$out/sets/$1/pairs.json" ] || "$bin" generate "$out/sets/$1" "${@:2}" > /dev/null; }
gen xA --count 20 --seed 100
gen xB --count 20 --seed 200 --mirror --noise 0.05 --explored 0.7
gen xC --count 20 --seed 300 --explored 0.4
gen hhsyn --count 50 --seed 500 --style handheld
gen hhx --count 12 --seed 600 --style handheld

m="$out/manifests"
"$python" "$here/scripts/cross_pairs.py" "$m/shared_rev.json" --reverse "$shared/pairs.json" > /dev/null
"$python" "$here/scripts/cross_pairs.py" "$m/hh_rev.json" --reverse "$shared/handheld/pairs.json" > /dev/null
"$python" "$here/scripts/cross_pairs.py" "$m/shxhh.json" --between "$shared/pairs.json" "$shared/handheld/pairs.json" \
  --only-b maps/F5_layout,maps/HIH_layout,maps/KPT4A_layout,maps/F5_01,maps/F5_08,maps/HIH_01,maps/KPT4A_01 --both > /dev/null
for s in xA xB xC hhx; do
  "$python" "$here/scripts/cross_pairs.py" "$m/${s}_rev.json" --reverse "$out/sets/$s/pairs.json" > /dev/null
done

# name, then the eval arguments
runs=(
  "shared|$shared/pairs.json --cross-buildings"
  "shared_rev|$m/shared_rev.json"
  "hh|$shared/handheld/pairs.json --no-reflection --cross-buildings"
  "hh_rev|$m/hh_rev.json"
  "hh_refl|$shared/handheld/pairs.json"
  "shxhh|$m/shxhh.json"
  "xA|$out/sets/xA/pairs.json --cross-buildings"
  "xA_rev|$m/xA_rev.json"
  "xB|$out/sets/xB/pairs.json --cross-buildings"
  "xB_rev|$m/xB_rev.json"
  "xC|$out/sets/xC/pairs.json --cross-buildings"
  "xC_rev|$m/xC_rev.json"
  "hhsyn|$out/sets/hhsyn/pairs.json --no-reflection"
  "hhx|$out/sets/hhx/pairs.json --no-reflection --cross-buildings"
  "hhx_rev|$m/hhx_rev.json"
)
run_one() {
  local name="${1%%|*}" args="${1#*|}"
  [ -f "$out/$name/results.csv" ] && return 0
  # shellcheck disable=SC2086
  "$bin" eval $args --picture-scale 8 --out "$out/$name.tmp" > "$out/$name.log" 2>&1 || { echo "eval $name failed: $out/$name.log" >&2; return 1; }
  rm -rf "$out/$name.tmp/pairs"
  mv "$out/$name.tmp" "$out/$name"
  echo "$name: $(tail -n 3 "$out/$name.log" | tr '\n' ' ')"
}
export -f run_one; export out bin
printf '%s\n' "${runs[@]}" | xargs -d '\n' -P "$jobs" -I{} bash -c 'run_one "$1"' _ {}
echo "rows in $out/*/results.csv"

# Simulated laser-SLAM maps of every shared layout, and each onto the other layouts, in their own
# folder (not in $out/*/results.csv): they choose the agreement gate's both-ways thresholds
# (`areamatch calibrate ... --simulated`) but do not train the model (trained on, they cost right answers
# of real hand-held scans: docs/evaluation.md).
sim="$out/simulated"
[ -f "$sim/set/eval/results.csv" ] || "$here/scripts/simulated_set.sh" "$sim/set" "$bin" > /dev/null
[ -f "$sim/onto_other_plans/results.csv" ] ||
  "$bin" eval "$sim/set/onto_other_plans.json" --picture-scale 8 --out "$sim/onto_other_plans.tmp" > "$sim/onto_other_plans.log" 2>&1
if [ -d "$sim/onto_other_plans.tmp" ]; then rm -rf "$sim/onto_other_plans.tmp/pairs"; mv "$sim/onto_other_plans.tmp" "$sim/onto_other_plans"; fi
echo "simulated rows in $sim/set/eval/results.csv and $sim/onto_other_plans/results.csv"
