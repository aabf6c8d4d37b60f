#!/usr/bin/env python3
"""The plain distance-transform watershed that issue 4 names as the baseline, scored like ours.

A common room segmentation (Bormann et al. 2016, "distance transform"): threshold the free
space's distance to the walls at the level that gives the most separate blobs of at least
MIN_ROOM_M2, and grow those blobs over the free space by a watershed. This script runs it on the
maps of a manifest and scores it with the reference scorers of ../shared/tools exactly as
scripts/segmentation_report.sh scores `areamatch segment`: room recall / precision on the layouts
with a hand-made segmentation, cross-modal consistency per pair. It is a yardstick, not part of
areamatch.

usage: scripts/watershed_baseline.py [MANIFEST]
needs python3-opencv and python3-numpy (as ../shared/tools do).
"""
import glob
import json
import os
import subprocess
import sys
import tempfile

import cv2
import numpy as np

MIN_ROOM_M2 = 1.0  # smallest blob of deep free space that seeds a room
MIN_FREE_M2 = 0.25  # free specks smaller than this are dropped (as areamatch's default)
LEVELS_M = np.arange(0.2, 1.5, 0.05)  # distance thresholds tried


def read_map(yaml_path):
    """Free-space mask and resolution of a ROS map_server YAML (trinary mode)."""
    meta = {}
    with open(yaml_path) as f:
        for line in f:
            if ":" in line:
                key, value = line.split(":", 1)
                meta[key.strip()] = value.strip()
    image = cv2.imread(os.path.join(os.path.dirname(yaml_path), meta["image"]), cv2.IMREAD_GRAYSCALE)
    if image is None:
        raise SystemExit("cannot read the image of " + yaml_path)
    p = image.astype(float) / 255 if meta.get("negate", "0") == "1" else (255 - image.astype(float)) / 255
    return p < float(meta.get("free_thresh", 0.196)), float(meta["resolution"])


def segment(yaml_path, out_png):
    free, res = read_map(yaml_path)
    count, blobs, stats, _ = cv2.connectedComponentsWithStats(free.astype(np.uint8), connectivity=4)
    keep = stats[:, cv2.CC_STAT_AREA] * res * res >= MIN_FREE_M2
    keep[0] = False
    free = keep[blobs]
    distance = cv2.distanceTransform(free.astype(np.uint8), cv2.DIST_L2, 5) * res
    best = None
    for level in LEVELS_M:
        count, blobs, stats, _ = cv2.connectedComponentsWithStats((distance > level).astype(np.uint8), connectivity=8)
        rooms = [i for i in range(1, count) if stats[i, cv2.CC_STAT_AREA] * res * res >= MIN_ROOM_M2]
        if best is None or len(rooms) > len(best[0]):
            best = (rooms, blobs)
    rooms, blobs = best
    markers = np.zeros(free.shape, np.int32)
    for k, i in enumerate(rooms, start=1):
        markers[blobs == i] = k
    walls = len(rooms) + 1
    markers[~free] = walls  # the walls are one basin of their own, so rooms grow in free space only
    cv2.watershed(cv2.cvtColor(free.astype(np.uint8) * 255, cv2.COLOR_GRAY2BGR), markers)
    labels = np.where(free & (markers > 0) & (markers < walls), markers, 0).astype(np.uint16)
    # Watershed lines (-1) inside free space go to a neighbouring room.
    lines = free & (labels == 0)
    labels[lines] = cv2.dilate(labels, np.ones((3, 3), np.uint8))[lines]
    cv2.imwrite(out_png, labels)


def tool(shared, name, *args):
    out = subprocess.run([sys.executable, os.path.join(shared, "tools", name)] + list(args), capture_output=True, text=True)
    return out.stdout.split()


def main():
    manifest_path = sys.argv[1] if len(sys.argv) > 1 else os.path.join("..", "shared", "pairs.json")
    shared = os.path.dirname(os.path.abspath(manifest_path))
    with open(manifest_path) as f:
        manifest = json.load(f)
    with tempfile.TemporaryDirectory() as tmp:
        scores = []
        print("%-19s %6s %9s" % ("map", "recall", "precision"))
        for gt in sorted(glob.glob(os.path.join(shared, "maps", "*_gt_segmentation.png"))):
            name = os.path.basename(gt)[: -len("_gt_segmentation.png")]
            labels = os.path.join(tmp, name + ".png")
            segment(os.path.join(shared, "maps", name + ".yaml"), labels)
            recall, precision = map(float, tool(shared, "segscore.py", labels, gt)[:2])
            scores.append((recall, precision))
            print("%-19s %6.3f %9.3f" % (name, recall, precision))
        if scores:
            print("mean over %d layouts: recall %.3f precision %.3f\n" % ((len(scores),) + tuple(np.mean(scores, axis=0))))
        by_kind = {}
        print("%-36s %-20s %s" % ("pair", "kind", "consistency dest_areas"))
        for pair in manifest["pairs"]:
            images = []
            for key in ("source", "destination"):
                images.append(os.path.join(tmp, "%s_%s.png" % (pair["name"], key)))
                segment(os.path.join(shared, pair[key]), images[-1])
            result = tool(shared, "consistency.py", images[0], images[1], json.dumps(pair["ground_truth"]["pixel_transform"]))
            by_kind.setdefault(pair["kind"], []).append(float(result[0]))
            print("%-36s %-20s %s %s" % (pair["name"], pair["kind"], result[0], result[1]))
        for kind, values in by_kind.items():
            print("%s: mean %.3f over %d pairs" % (kind, np.mean(values), len(values)))


if __name__ == "__main__":
    sys.exit(main())
