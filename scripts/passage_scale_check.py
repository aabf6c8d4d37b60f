#!/usr/bin/env python3
"""Check a manifest's ground-truth scales against the maps' own door positions.

For each pair: segment both maps with `areamatch segment` (the source at its ground-truth
resolution), carry the source's passages into the destination with the ground-truth pixel
transform, pair mutually nearest passages closer than --gate pixels, and fit a similarity to the
pairs. Its scale factor is 1 when the ground truth's scale lays the doors onto each other; the
residual says how well one similarity explains the door positions at all.

Door positions do not move when a SLAM map's free space stops short of the walls (clutter), so
this separates "the matcher's scale is biased" from "the ground truth's scale is off".

usage: scripts/passage_scale_check.py [MANIFEST] [--areamatch PATH] [--gate PX]
needs numpy.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np


def passages_px(areamatch, path, resolution, out_json):
    """Passage positions of the map at `path`, segmented at `resolution`, in image pixels."""
    subprocess.run([areamatch, "segment", path, "--resolution", repr(resolution), "--graph", out_json],
                   check=True, capture_output=True)
    with open(out_json) as f:
        graph = json.load(f)
    info = graph["map"]
    ox, oy = info["origin"][0], info["origin"][1]
    height = info["height"]
    return np.array([[(q["position"][0] - ox) / resolution, height - (q["position"][1] - oy) / resolution]
                     for q in graph["passages"]]).reshape(-1, 2)


def similarity_scale(a, b):
    """Scale of the least-squares similarity (rotation allowed) taking points a onto b, and its RMS residual."""
    a0, b0 = a - a.mean(0), b - b.mean(0)
    u, s, vt = np.linalg.svd(a0.T @ b0)
    d = np.sign(np.linalg.det(vt.T @ u.T))
    rot = vt.T @ np.diag([1.0, d]) @ u.T
    scale = (s[0] + d * s[1]) / (a0 ** 2).sum()
    residual = b0 - scale * a0 @ rot.T
    return scale, float(np.sqrt((residual ** 2).sum(1).mean()))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("manifest", nargs="?", default=os.path.join(here, "..", "..", "shared", "pairs.json"))
    ap.add_argument("--areamatch", default=os.path.join(here, "..", "build", "tools", "areamatch"))
    ap.add_argument("--gate", type=float, default=20.0, help="largest door distance in pixels under the ground truth")
    args = ap.parse_args()
    base = os.path.dirname(os.path.abspath(args.manifest))
    with open(args.manifest) as f:
        pairs = json.load(f)["pairs"]
    print(f"{'pair':36s} {'doors':>9s} {'mean px':>8s} {'factor':>7s} {'rms px':>7s} {'gt scale':>9s} {'door scale':>10s}")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "graph.json")
        for p in pairs:
            gt = p.get("ground_truth")
            if not gt or "pixel_transform" not in gt:
                continue
            m = np.array(gt["pixel_transform"], dtype=float)
            gt_scale = float(gt.get("scale", np.sqrt(abs(np.linalg.det(m[:, :2])))))
            dest_res = float(p.get("destination_resolution", 0.05))
            src = passages_px(args.areamatch, os.path.join(base, p["source"]), dest_res * gt_scale, out)
            dst = passages_px(args.areamatch, os.path.join(base, p["destination"]), dest_res, out)
            if len(src) == 0 or len(dst) == 0:
                print(f"{p['name']:36s} no passages")
                continue
            moved = src @ m[:, :2].T + m[:, 2]
            dist = np.linalg.norm(moved[:, None, :] - dst[None, :, :], axis=2)
            pairs_ij = [(i, int(dist[i].argmin())) for i in range(len(src))
                        if dist[i].min() < args.gate and int(dist[:, dist[i].argmin()].argmin()) == i]
            if len(pairs_ij) < 3:
                print(f"{p['name']:36s} {len(pairs_ij):>9d} too few door pairs")
                continue
            a = moved[[i for i, _ in pairs_ij]]
            b = dst[[j for _, j in pairs_ij]]
            factor, rms = similarity_scale(a, b)
            mean_px = float(np.mean([dist[i, j] for i, j in pairs_ij]))
            print(f"{p['name']:36s} {len(pairs_ij):>9d} {mean_px:8.1f} {factor:7.4f} {rms:7.1f} {gt_scale:9.4f} {gt_scale * factor:10.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
