#!/usr/bin/env python3
"""How high cross-modal consistency can go when the source map does not cover the destination.

consistency.py counts a destination area as consistent when some source area, carried over by
the ground truth, overlaps it with IoU >= 0.5. That needs at least half of the destination area
to be covered by labelled source space: rooms the robot never entered, or only glimpsed through
a door, cannot count whatever the segmentation does. For each pair of a manifest this segments
both maps with `areamatch segment` and reports the consistency next to that ceiling (the share
of destination areas >= 0.5 m^2 at least half covered by any source area) and next to what the
best merging of the source's areas reaches ("merged": an oracle that knows the ground truth joins
every source area to the destination area holding most of it, then scores as consistency.py).
No rule that only merges source areas can score above "merged"; splits the source map makes
across a destination room (walls or furniture the other map does not have) stay in it. The
"matched" column scores the source labels of `areamatch match SRC DST --allow-reflection
--labels` (each source area named by the destination area it corresponds to, found by the
matcher without the ground truth); it is left out when segment options are given.

usage: scripts/consistency_bound.py [MANIFEST] [--areamatch PATH] [--kind KIND] [-- SEGMENT OPTIONS]
needs python3-opencv and python3-numpy (as ../shared/tools/consistency.py does).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import cv2
import numpy as np


def labels_of(areamatch, path, out_png, extra):
    subprocess.run([areamatch, "segment", path, "--labels", out_png] + extra, check=False, capture_output=True)
    image = cv2.imread(out_png, cv2.IMREAD_UNCHANGED)
    if image is None:
        return None
    return image[:, :, 0] if image.ndim == 3 else image


def warp(labels, pair, shape):
    G = np.array(pair["ground_truth"]["pixel_transform"], float)
    return cv2.warpAffine(labels.astype(np.float32), G, (shape[1], shape[0]), flags=cv2.INTER_NEAREST,
                          borderValue=0).astype(np.int64)


def consistent(warped, dst):
    """Per destination area >= 0.5 m^2 (200 cells at 5 cm, as consistency.py): whether some
    warped source label overlaps it with IoU >= 0.5."""
    warped_size = dict(zip(*np.unique(warped, return_counts=True)))
    out = {}
    for value in np.unique(dst):
        mask = dst == value
        size = int(mask.sum())
        if value == 0 or size < 200:
            continue
        values, overlap = np.unique(warped[mask], return_counts=True)
        out[value] = max((c / (size + warped_size[v] - c) for v, c in zip(values, overlap) if v != 0), default=0.0) >= 0.5
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("manifest", nargs="?", default=os.path.join("..", "shared", "pairs.json"))
    parser.add_argument("--areamatch", default=os.path.join("build", "tools", "areamatch"))
    parser.add_argument("--kind", default="slam_to_layout", help="pairs of this kind only ('' for all)")
    # Everything after "--" goes to `areamatch segment` unparsed (argparse would take its first
    # word for the manifest).
    argv = sys.argv[1:]
    cut = argv.index("--") if "--" in argv else len(argv)
    args = parser.parse_args(argv[:cut])
    extra = argv[cut + 1:]
    with open(args.manifest) as f:
        manifest = json.load(f)
    root = os.path.dirname(os.path.abspath(args.manifest))
    print("%-36s %11s %8s %8s %8s %10s" % ("pair", "consistency", "merged", "matched", "ceiling", "dst_areas"))
    totals = []
    with tempfile.TemporaryDirectory() as tmp:
        for pair in manifest["pairs"]:
            if args.kind and pair.get("kind") != args.kind:
                continue
            source, destination = os.path.join(root, pair["source"]), os.path.join(root, pair["destination"])
            src = labels_of(args.areamatch, source, os.path.join(tmp, "s.png"), extra)
            dst = labels_of(args.areamatch, destination, os.path.join(tmp, "d.png"), extra)
            if src is None or dst is None:
                print("%-36s segmentation failed" % pair["name"])
                continue
            warped = warp(src, pair, dst.shape)
            plain = consistent(warped, dst)
            if not plain:
                continue
            # The merge oracle: each warped source area joins the destination area (or the outside,
            # 0) that holds most of it.
            merged = np.zeros_like(warped)
            for value in np.unique(warped):
                if value != 0:
                    area = warped == value
                    values, overlap = np.unique(dst[area], return_counts=True)
                    merged[area] = values[np.argmax(overlap)]
            merged_ok = consistent(merged, dst)
            coverable = {value: (warped[dst == value] > 0).mean() >= 0.5 for value in plain}
            matched = float("nan")
            if not extra:
                door = ["--door-width", str(pair["door_width_m"])] if "door_width_m" in pair else []
                matched_png = os.path.join(tmp, "m.png")
                if os.path.exists(matched_png):
                    os.remove(matched_png)
                subprocess.run([args.areamatch, "match", source, destination, "--allow-reflection", "--labels", matched_png]
                               + door, check=False, capture_output=True)
                image = cv2.imread(matched_png, cv2.IMREAD_UNCHANGED)
                if image is not None and image.ndim == 3:
                    image = image[:, :, 0]
                matched_ok = consistent(warp(image, pair, dst.shape), dst) if image is not None else {}
                matched = sum(matched_ok.values()) / len(plain)
            count = len(plain)
            row = (sum(plain.values()) / count, sum(merged_ok.values()) / count, matched, sum(coverable.values()) / count)
            totals.append(row)
            print("%-36s %11.3f %8.3f %8.3f %8.3f %10d" % ((pair["name"],) + row + (count,)))
    if totals:
        print("%-36s %11.3f %8.3f %8.3f %8.3f" % (("mean of %d pairs" % len(totals),) + tuple(np.mean(totals, axis=0))))

if __name__ == "__main__":
    sys.exit(main())
