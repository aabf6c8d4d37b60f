#!/usr/bin/env bash
# Writes what a build of the program answers on the shared and hand-held data, timings removed,
# so that two builds can be compared byte for byte (a refactoring or speed-up must not change
# an answer):
#   eval CSVs: shared pairs with --cross-buildings, --paper, hand-held pairs --no-reflection,
#              --estimate-scale on three pairs (columns ending in _ms dropped);
#   the F5 merge JSON (timings dropped);
#   segment --labels/--graph of every map (keys ending in _s/_ms and "timings" dropped).
#   scripts/outputs_digest.sh AREAMATCH_BINARY OUT_DIR     (~3 min on 2 cores)
# then e.g. `diff -r OLD_DIR NEW_DIR`. Needs ../shared and python3.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="$(realpath "$1")"; out="$2"
shared="$(realpath "$here/../shared")"; hh="$shared/handheld"
mkdir -p "$out/segment"
csv_without_times() { python3 - "$1" "$2" <<'PY'
import csv, sys
rows = csv.reader(open(sys.argv[1])); out = csv.writer(open(sys.argv[2], "w"))
head = next(rows); keep = [i for i, c in enumerate(head) if not c.endswith("_ms")]
out.writerow([head[i] for i in keep])
for row in rows: out.writerow([row[i] for i in keep])
PY
}
json_without_times() { python3 -c '
import json, sys
def strip(o):
    if isinstance(o, dict): return {k: strip(v) for k, v in o.items() if not (k.endswith("_s") or k.endswith("_ms") or k == "timings")}
    if isinstance(o, list): return [strip(v) for v in o]
    return o
print(json.dumps(strip(json.load(sys.stdin)), sort_keys=True))'; }
evaluate() {
  local name=$1; shift
  "$bin" eval "$@" --picture-scale 8 --out "$out/$name.tmp" > /dev/null 2>&1 || true
  csv_without_times "$out/$name.tmp/results.csv" "$out/$name.csv"
  rm -rf "$out/$name.tmp"
}
evaluate shared "$shared/pairs.json" --cross-buildings
evaluate paper "$shared/pairs.json" --paper
evaluate handheld "$hh/pairs.json" --no-reflection
evaluate scale "$shared/pairs.json" --estimate-scale --only lab_b_rot123,freiburg52,ipa_map_pgm
"$bin" merge "$hh/maps/F5_layout.yaml" "$hh"/maps/F5_??.yaml --door-width 1.0 --json 2> /dev/null | json_without_times > "$out/merge_F5.json" || true
# The graph file's option: --graph since `--json` became a flag; --json FILE in older builds.
graph_option=--graph
"$bin" segment --help | grep -q -- '--graph' || graph_option=--json
for yaml in "$shared"/maps/*.yaml "$hh"/maps/*.yaml; do
  name=$(basename "$yaml" .yaml)
  "$bin" segment "$yaml" --labels "$out/segment/$name.png" "$graph_option" "$out/segment/$name.raw.json" > /dev/null 2>&1 || true
  json_without_times < "$out/segment/$name.raw.json" > "$out/segment/$name.json" 2> /dev/null || true
  rm -f "$out/segment/$name.raw.json"
done
(cd "$out" && find . -type f | sort | xargs md5sum) > "$out.md5"
echo "wrote $out (digest: $out.md5)"
