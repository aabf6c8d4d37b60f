#!/usr/bin/env python3
"""Scores `areamatch merge` on the hand-held places of ../shared/handheld against their ground truth.

score_merge.py [--areamatch BIN] [--handheld DIR] [--place F5,HIH,KPT4A] [--png-dir DIR] [--json OUT]
               [--merge-args '...']

For each place, merges its layout and all its scans with the layout as the reference
(`areamatch merge LAYOUT SCAN... --door-width W --json`, W the place's door_width_m in
pairs.json) and judges each scan's placement (its pixel transform onto the layout) against the
scan -> layout ground truth of pairs.json by the rule of ../shared/tools/score.py: correct when
the rotation error is at most correct_if.max_rotation_error_deg and the mean displacement of the
scan's free-space edge points at most correct_if.max_mean_displacement_m. A scan left unplaced is
not placed wrongly; a scan placed outside those bounds is. Standard library only (score.py needs
OpenCV and NumPy; this reads the trinary 8-bit grey PNGs itself and samples the points the same
way). Exit status: 0 when every place has at most one scan not placed correctly and none placed
wrongly (the target of issue 24), 1 otherwise, 2 on bad input.
"""
import argparse, json, math, os, struct, subprocess, sys, zlib


def read_grey_png(path):
    """Width, height and the rows (bytes) of an 8-bit grey, non-interlaced PNG."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit("%s: not a PNG" % path)
    pos, idat, header = 8, [], None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour != 0 or interlace:
        raise SystemExit("%s: only 8-bit grey non-interlaced PNGs are read here" % path)
    raw = zlib.decompress(b"".join(idat))
    rows, previous = [], bytearray(width)
    for r in range(height):
        start = r * (width + 1)
        kind, line = raw[start], bytearray(raw[start + 1:start + 1 + width])
        if kind == 1:
            for i in range(1, width): line[i] = (line[i] + line[i - 1]) & 255
        elif kind == 2:
            line = bytearray((a + b) & 255 for a, b in zip(line, previous))
        elif kind == 3:
            for i in range(width):
                left = line[i - 1] if i else 0
                line[i] = (line[i] + ((left + previous[i]) >> 1)) & 255
        elif kind == 4:
            for i in range(width):
                a = line[i - 1] if i else 0
                b, c = previous[i], previous[i - 1] if i else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        previous = line
    return width, height, rows


def free_edge_points(path):
    """score.py's points: free pixels (>= 240) with a pixel that is not free in their 3x3
    neighbourhood (outside the image counts as free, as cv2.erode pads for erosion), at most
    20000 taken evenly in row order."""
    width, height, rows = read_grey_png(path)
    free = [b"\x01" + bytes(1 if v >= 240 else 0 for v in row) + b"\x01" for row in rows]
    border = b"\x01" * (width + 2)
    points = []
    for r in range(height):
        row = free[r]
        up, down = free[r - 1] if r else border, free[r + 1] if r + 1 < height else border
        for c in range(1, width + 1):
            if row[c] and not (up[c - 1] and up[c] and up[c + 1] and row[c - 1] and row[c + 1] and
                               down[c - 1] and down[c] and down[c + 1]):
                points.append((c - 1, r))
    if len(points) > 20000:  # np.linspace(0, n - 1, 20000).astype(int)
        n = len(points)
        points = [points[int(i * (n - 1) / 19999)] for i in range(20000)]
    return points


def angle_and_reflection(m):
    a, b, c, d = m[0][0], m[0][1], m[1][0], m[1][1]
    reflected = a * d - b * c < 0
    if reflected:
        b, d = -b, -d
    return math.degrees(math.atan2(c, a)), reflected


def apply(m, p):
    return (m[0][0] * p[0] + m[0][1] * p[1] + m[0][2], m[1][0] * p[0] + m[1][1] * p[1] + m[1][2])


def read_yaml(path):
    return {k.strip(): v.strip() for k, v in (line.split(":", 1) for line in open(path) if ":" in line)}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--areamatch", default=os.path.join(here, "..", "build", "tools", "areamatch"))
    ap.add_argument("--handheld", default=os.path.join(here, "..", "..", "shared", "handheld"))
    ap.add_argument("--place", default="F5,HIH,KPT4A")
    ap.add_argument("--png-dir", default="", help="write each place's merged picture here")
    ap.add_argument("--json", default="", help="write the per-scan rows here")
    ap.add_argument("--merge-args", default="", help="more options for areamatch merge, e.g. '--until-connected'")
    a = ap.parse_args()
    manifest_path = os.path.join(a.handheld, "pairs.json")
    if not os.path.exists(manifest_path):
        print("score_merge.py: %s not found" % manifest_path, file=sys.stderr)
        return 2
    manifest = json.load(open(manifest_path))
    limits = manifest.get("correct_if", {})
    max_rot, max_disp = limits.get("max_rotation_error_deg", 3.0), limits.get("max_mean_displacement_m", 1.0)
    all_rows, target_met = [], True
    for place in filter(None, a.place.split(",")):
        pairs = [p for p in manifest["pairs"] if p["kind"] == "sensor_to_layout" and p["name"].startswith(place + "_")]
        if not pairs:
            print("score_merge.py: no scan -> layout pairs of %s" % place, file=sys.stderr)
            return 2
        layout = os.path.join(a.handheld, pairs[0]["destination"])
        scans = [os.path.join(a.handheld, p["source"]) for p in pairs]
        command = [a.areamatch, "merge", layout] + scans + ["--door-width", str(pairs[0].get("door_width_m", 1.0)), "--json"]
        command += a.merge_args.split()
        if a.png_dir:
            command += ["--png", os.path.join(a.png_dir, place + "_merged.png")]
        run = subprocess.run(command, capture_output=True, text=True)
        if run.returncode not in (0, 1) or not run.stdout.strip():
            print("score_merge.py: %s failed (%s): %s" % (" ".join(command), run.returncode, run.stderr.strip()), file=sys.stderr)
            return 2
        merged = json.loads(run.stdout.strip().splitlines()[-1])
        by_path = {m["path"]: m for m in merged["maps"]}
        dest_resolution = float(read_yaml(layout)["resolution"])
        correct = wrong = unplaced = 0
        for pair, scan in zip(pairs, scans):
            m = by_path[scan]
            row = {"place": place, "name": pair["name"], "placed": m["placed"], "rot_err": None, "disp_m": None, "correct": False}
            if m["placed"]:
                E, G = m["pixel_transform"], pair["ground_truth"]["pixel_transform"]
                source_image = os.path.join(os.path.dirname(scan), read_yaml(scan)["image"])
                points = free_edge_points(source_image)
                disp = sum(math.dist(apply(E, p), apply(G, p)) for p in points) / max(1, len(points)) * dest_resolution
                (ae, re_), (ag, rg) = angle_and_reflection(E), angle_and_reflection(G)
                rot_err = abs((ae - ag + 180) % 360 - 180) if re_ == rg else 180.0
                row.update(rot_err=rot_err, disp_m=disp, correct=rot_err <= max_rot and disp <= max_disp)
                correct += row["correct"]
                wrong += not row["correct"]
            else:
                row["reason"] = m.get("reason", "")
                unplaced += 1
            all_rows.append(row)
            print("%-22s %-10s rot_err=%7s disp=%8s %s" % (
                pair["name"], "placed" if m["placed"] else "unplaced",
                "%.2f" % row["rot_err"] if row["rot_err"] is not None else "-",
                "%.3fm" % row["disp_m"] if row["disp_m"] is not None else "-",
                "CORRECT" if row["correct"] else ("wrong" if m["placed"] else row["reason"])), flush=True)
        met = wrong == 0 and correct >= len(pairs) - 1
        target_met = target_met and met
        edges = merged["edges"]
        print("%s: %d/%d scans placed correctly, %d placed wrongly, %d not placed; %d matches, %d accepted, %d used; "
              "merge %.2f s (total %.2f s)%s" % (
            place, correct, len(pairs), wrong, unplaced, len(edges), sum(e["ok"] for e in edges), sum(e["used"] for e in edges),
            merged["timings"]["merge_s"], merged["timings"]["total_s"],
            "" if met else "  [target not met]"), flush=True)
    if a.json:
        json.dump(all_rows, open(a.json, "w"), indent=1)
    return 0 if target_met else 1


if __name__ == "__main__":
    sys.exit(main())
