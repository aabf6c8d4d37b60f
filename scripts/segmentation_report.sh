#!/usr/bin/env bash
# Regenerates the segmentation quality tables of docs/segmentation.md with the reference scorers
# of ../shared/tools (needs the build, ../shared and: apt-get install python3-opencv python3-numpy).
#   scripts/segmentation_report.sh [extra 'areamatch segment' options, e.g. --door-width 1.5]
# Prints room recall/precision per layout with a ground truth, then the cross-modal consistency
# of every pair of ../shared/pairs.json, with means.
set -euo pipefail
cd "$(dirname "$0")/.."
areamatch="${AREAMATCH_BUILD_DIR:-build}/tools/areamatch"
shared="${AREAMATCH_SHARED_DIR:-../shared}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
python=/usr/bin/python3

echo "map                 recall precision gt_rooms areas"
for gt in "$shared"/maps/*_gt_segmentation.png; do
  map=$(basename "$gt" _gt_segmentation.png)
  "$areamatch" segment "$shared/maps/$map.yaml" --labels "$out/$map.png" "$@" > /dev/null || true
  printf "%-19s %s\n" "$map" "$("$python" "$shared/tools/segscore.py" "$out/$map.png" "$gt")"
done | tee "$out/scores.txt"
awk 'NF>=3 {r+=$2; p+=$3; n++} END {printf "mean over %d layouts: recall %.3f precision %.3f\n\n", n, r/n, p/n}' "$out/scores.txt"

"$python" - "$areamatch" "$shared" "$out" "$@" <<'PY'
import json, os, subprocess, sys
areamatch, shared, out, extra = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
manifest = json.load(open(os.path.join(shared, "pairs.json")))
by_kind = {}
print("%-36s %-20s %s" % ("pair", "kind", "consistency dest_areas"))
for pair in manifest["pairs"]:
    labels = []
    for key in ("source", "destination"):
        path = os.path.join(shared, pair[key])
        image = os.path.join(out, pair["name"] + "_" + key + ".png")
        door = ["--door-width", str(pair["door_width_m"])] if "door_width_m" in pair else []
        subprocess.run([areamatch, "segment", path, "--labels", image] + door + extra, capture_output=True)
        labels.append(image)
    result = subprocess.run([sys.executable, os.path.join(shared, "tools", "consistency.py"), labels[0], labels[1],
                             json.dumps(pair["ground_truth"]["pixel_transform"])], capture_output=True, text=True).stdout.split()
    by_kind.setdefault(pair["kind"], []).append(float(result[0]))
    print("%-36s %-20s %s %s" % (pair["name"], pair["kind"], result[0], result[1]))
for kind, values in by_kind.items():
    print("%s: mean %.3f over %d pairs" % (kind, sum(values) / len(values), len(values)))
PY
