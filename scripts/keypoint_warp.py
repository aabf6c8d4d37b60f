#!/usr/bin/env python3
"""Judges areamatch's warp on hand-picked keypoints it never sees (docs/warp.md).

For every pair of a manifest with keypoints (shared/handheld/pairs.json and keypoints.json), runs
`areamatch warp SOURCE DEST --points KEYPOINTS --json` (the pair's door width, no reflection: the
hand-held data is not mirrored) and measures, in destination metres, each kept keypoint's error
  - under the warp,
  - under areamatch's own rigid answer (the match's pixel transform),
  - under the ground truth: the least-squares similarity fitted to these very keypoints, the best
    any rigid transform can do on them.
Prints the median per building and kind, and the warp's median as a share of the rigid fit's.

  scripts/keypoint_warp.py [AREAMATCH] [MANIFEST] [KEYPOINTS] [-- extra warp options]
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

here = os.path.dirname(os.path.abspath(__file__))
args = sys.argv[1:]
extra = []
if "--" in args:
    extra = args[args.index("--") + 1:]
    args = args[:args.index("--")]
binary = args[0] if len(args) > 0 else os.path.join(here, "..", "build", "tools", "areamatch")
manifest_path = args[1] if len(args) > 1 else os.path.join(here, "..", "..", "shared", "handheld", "pairs.json")
keypoints_path = args[2] if len(args) > 2 else os.path.join(os.path.dirname(manifest_path), "keypoints.json")
folder = os.path.dirname(os.path.abspath(manifest_path))
manifest = json.load(open(manifest_path))
keypoints = json.load(open(keypoints_path))["pairs"]


def resolution(yaml_path):
    for line in open(yaml_path):
        if line.strip().startswith("resolution:"):
            return float(line.split(":", 1)[1])
    raise SystemExit(f"{yaml_path}: no resolution")


def apply(matrix, point):
    return (matrix[0][0] * point[0] + matrix[0][1] * point[1] + matrix[0][2],
            matrix[1][0] * point[0] + matrix[1][1] * point[1] + matrix[1][2])


def distance(a, b):
    return ((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2) ** 0.5


groups = {}
rows = []
with tempfile.TemporaryDirectory() as tmp:
    for pair in manifest["pairs"]:
        if pair.get("ambiguous") or pair["name"] not in keypoints:
            continue
        kept = [k for k in keypoints[pair["name"]] if not k["dropped"]]
        if not kept:
            continue
        points = os.path.join(tmp, "points.csv")
        with open(points, "w") as f:
            f.write("# col,row of the source's keypoints\n")
            for k in kept:
                f.write(f"{k['source'][0]},{k['source'][1]}\n")
        source = os.path.join(folder, pair["source"])
        dest = os.path.join(folder, pair["destination"])
        command = [binary, "warp", source, dest, "--points", points, "--json"] + extra
        if "door_width_m" in pair:
            command += ["--door-width", str(pair["door_width_m"])]
        run = subprocess.run(command, capture_output=True, text=True)
        if run.returncode == 2:
            raise SystemExit(f"{pair['name']}: {run.stderr.strip()}")
        out = json.loads(run.stdout)
        dest_res = resolution(dest)
        building = pair["name"].split("_")[0]
        kind = pair["kind"]
        truth = pair["ground_truth"]["pixel_transform"]
        errors = {"gt": [], "rigid": [], "warp": []}
        ok = out["match"]["ok"]
        for i, k in enumerate(kept):
            errors["gt"].append(distance(apply(truth, k["source"]), k["destination"]) * dest_res)
            if ok:
                errors["rigid"].append(distance(apply(out["match"]["pixel_transform"], k["source"]), k["destination"]) * dest_res)
                errors["warp"].append(distance(out["points"][i], k["destination"]) * dest_res)
        g = groups.setdefault((building, kind), {"gt": [], "rigid": [], "warp": [], "pairs": 0, "matched": 0})
        g["pairs"] += 1
        g["matched"] += ok
        # Only pairs areamatch matched count, so that the three columns judge the same keypoints.
        if ok:
            for key in ("gt", "rigid", "warp"):
                g[key] += errors[key]
        rows.append((pair["name"], ok, *(statistics.median(errors[key]) if errors[key] else float("nan")
                                         for key in ("gt", "rigid", "warp"))))

print("pair,matched,gt_fit_median_m,rigid_median_m,warp_median_m")
for r in rows:
    print(f"{r[0]},{int(r[1])},{r[2]:.3f},{r[3]:.3f},{r[4]:.3f}")
print()
print("| building | kind | pairs matched | keypoints | rigid fit to the keypoints (median, m) | areamatch rigid | areamatch warp | warp / fit |")
print("|---|---|---:|---:|---:|---:|---:|---:|")
totals = {}
for (building, kind), g in sorted(groups.items()):
    t = totals.setdefault(kind, {"gt": [], "rigid": [], "warp": [], "pairs": 0, "matched": 0})
    for key in ("gt", "rigid", "warp"):
        t[key] += g[key]
    t["pairs"] += g["pairs"]
    t["matched"] += g["matched"]
for (building, kind), g in sorted(groups.items()) + [(("all", k), t) for k, t in sorted(totals.items())]:
    if not g["warp"]:
        print(f"| {building} | {kind} | 0 / {g['pairs']} | | | | | |")
        continue
    gt, rigid, warp = (statistics.median(g[key]) for key in ("gt", "rigid", "warp"))
    print(f"| {building} | {kind} | {g['matched']} / {g['pairs']} | {len(g['warp'])} | {gt:.3f} | {rigid:.3f} | {warp:.3f} | {warp / gt:.2f} |")
