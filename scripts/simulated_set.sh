#!/usr/bin/env bash
# A simulated laser-SLAM set over every layout of ../shared/maps (docs/synthetic.md): per layout,
# 4 maps and 3 mirrored ones (seeds 1-7, golden-angle turns), each onto its layout with the door
# width its real pairs use, and one manifest of them all; then `areamatch eval` of it. Also writes
# OUT/onto_other_plans.json, each simulated map onto every other plan (scripts/calibration_data.sh).
#   scripts/simulated_set.sh OUT [AREAMATCH_BINARY] [extra simulate options, e.g. --binary --bend 0.5]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:?usage: scripts/simulated_set.sh OUT [AREAMATCH_BINARY] [simulate options]}"
bin="$(realpath "${2:-$here/build/tools/areamatch}")"
shift $(( $# >= 2 ? 2 : 1 ))
maps="$(realpath "$here/../shared/maps")"
python="python3"; [ -x /usr/bin/python3 ] && python=/usr/bin/python3
mkdir -p "$out"
layouts=(Freiburg52_scan Freiburg79_scan NLB lab_b_scan lab_ipa lab_intel office_a office_b office_c office_d office_e office_f office_g office_h office_i)
for layout in "${layouts[@]}"; do
  door=()
  [ "$layout" = lab_intel ] && door=(--door-width 2.5)  # as the intel pairs of shared/pairs.json
  "$bin" simulate "$maps/$layout.yaml" "$out/$layout" --count 4 --seed 1 "${door[@]}" "$@" > /dev/null &
  "$bin" simulate "$maps/$layout.yaml" "$out/${layout}_mirrored" --count 3 --seed 5 --mirror "${door[@]}" "$@" > /dev/null &
  wait
done
"$python" - "$out" "${layouts[@]}" <<'PY'
import json, os, sys
out, layouts = sys.argv[1], sys.argv[2:]
pairs = []
for layout in layouts:
    for folder in (layout, layout + "_mirrored"):
        m = json.load(open(os.path.join(out, folder, "pairs.json")))
        for p in m["pairs"]:
            p["source"] = os.path.join(folder, p["source"])
            p["name"] = folder + "_" + p["name"].split("_")[-1]
            pairs.append(p)
json.dump({"description": "Simulated laser-SLAM maps of every shared layout (scripts/simulated_set.sh).",
           "correct_if": {"max_rotation_error_deg": 3.0, "max_mean_displacement_m": 1.0}, "pairs": pairs},
          open(os.path.join(out, "pairs.json"), "w"), indent=1)
print(len(pairs), "pairs in", os.path.join(out, "pairs.json"))
# Each simulated map onto every other plan: pairs that must be refused.
plans = sorted(set(p["destination"] for p in pairs))
others = [{"name": p["name"] + " x " + os.path.basename(plan), "kind": "different_buildings",
           "source": os.path.abspath(os.path.join(out, p["source"])), "destination": plan,
           "allow_reflection": True, "different_buildings": True}
          for p in pairs for plan in plans if plan != p["destination"]]
json.dump({"description": "Simulated laser-SLAM maps onto the other plans (scripts/simulated_set.sh).",
           "correct_if": {"max_rotation_error_deg": 3.0, "max_mean_displacement_m": 1.0}, "pairs": others},
          open(os.path.join(out, "onto_other_plans.json"), "w"), indent=1)
PY
"$bin" eval "$out/pairs.json" --out "$out/eval" 2> "$out/eval.log" | tail -n 4
