#!/usr/bin/env python3
"""How matching cost grows with the floor (issue 44): generated buildings from 30 x 20 m to
400 x 300 m (`areamatch generate --width W --height H --seed 7`, the 400 x 300 m one unturned),
each robot map matched onto its layout by `areamatch match --json` in a fresh process, ROUNDS
times (median). Per size: areas, wall time, peak memory (/usr/bin/time), the stages' times from
the JSON, and time and memory per square metre relative to 60 x 40 m. With two binaries, each
round runs both, alternating, so that they see the same machine.

  scripts/growth.py OUTDIR [--rounds N] [--sizes 30x20,60x40,...] BINARY [BINARY2]

Writes OUTDIR/growth.csv and prints a markdown table. Refusals (too many areas, a grid too
large) are rows with the reason, not failures of the script.
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys

STAGES = ["segment_source_s", "segment_dest_s", "prepare_s", "features_s", "hypotheses_s", "clustering_s",
          "selection_s", "match_s"]


def generate(binary, folder, width, height):
    if os.path.exists(os.path.join(folder, "robot.yaml")):
        return
    extra = ["--rotation", "0"] if width * height > 240 * 160 else []
    subprocess.run([binary, "generate", folder, "--width", str(width), "--height", str(height), "--seed", "7"] + extra,
                   check=True, stdout=subprocess.DEVNULL)


def run_once(binary, folder):
    """(wall s, peak KB, JSON or None, refusal text)."""
    command = ["/usr/bin/time", "-f", "TIME %e %M", binary, "match", os.path.join(folder, "robot.yaml"),
               os.path.join(folder, "layout.yaml"), "--json"]
    p = subprocess.run(command, capture_output=True, text=True)
    line = [l for l in p.stderr.splitlines() if l.startswith("TIME ")][-1].split()
    wall, peak = float(line[1]), int(line[2])
    result = json.loads(p.stdout) if p.stdout.strip().startswith("{") else None
    refusal = "" if p.returncode in (0, 1) else p.stderr.splitlines()[0][:160]
    return wall, peak, result, refusal


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("outdir")
    parser.add_argument("binaries", nargs="+")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--sizes", default="30x20,60x40,120x80,240x160,400x300")
    args = parser.parse_args()
    os.makedirs(args.outdir, exist_ok=True)
    sizes = [tuple(int(v) for v in s.split("x")) for s in args.sizes.split(",")]
    binaries = [os.path.realpath(b) for b in args.binaries]
    rows = []
    for width, height in sizes:
        folder = os.path.join(args.outdir, f"{width}x{height}")
        generate(binaries[-1], folder, width, height)
        runs = {b: [] for b in binaries}
        for r in range(args.rounds):
            for b in (binaries if r % 2 == 0 else binaries[::-1]):
                runs[b].append(run_once(b, folder))
        for label, b in zip(["new", "old"] if len(binaries) == 2 else ["", ""], binaries):
            got = runs[b]
            result = got[-1][2]
            row = {"binary": label or os.path.basename(b), "size": f"{width}x{height}", "m2": width * height,
                   "wall_s": statistics.median(g[0] for g in got), "peak_mb": max(g[1] for g in got) / 1024.0,
                   "refusal": got[-1][3] or ("" if result is None or result.get("ok") else "rejected: " + result["reason"][:80]),
                   "ok": bool(result and result.get("ok"))}
            if result:
                row["areas"] = f"{result['statistics']['source_areas']} / {result['statistics']['dest_areas']}"
                for s in STAGES:
                    row[s] = statistics.median(g[2]["timings"][s] for g in got if g[2])
            rows.append(row)
            print(f"{row['size']} {row['binary']}: {row['wall_s']:.2f} s, {row['peak_mb']:.0f} MB {row['refusal']}",
                  file=sys.stderr)
    base = {r["binary"]: r for r in rows if r["size"] == "60x40"}
    for r in rows:
        b = base.get(r["binary"])
        if b:
            r["time_per_m2_vs_60x40"] = (r["wall_s"] / r["m2"]) / (b["wall_s"] / b["m2"])
            r["memory_per_m2_vs_60x40"] = (r["peak_mb"] / r["m2"]) / (b["peak_mb"] / b["m2"])
    fields = ["binary", "size", "m2", "areas", "ok", "wall_s", "peak_mb", "time_per_m2_vs_60x40",
              "memory_per_m2_vs_60x40"] + STAGES + ["refusal"]
    with open(os.path.join(args.outdir, "growth.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    print("| binary | building | areas (robot / layout) | accepted | wall | peak memory | time / m² (× 60 × 40) "
          "| memory / m² (× 60 × 40) | segment robot / layout | prepare | features | selection |")
    print("|---|---|---:|---|---:|---:|---:|---:|---|---:|---:|---:|")
    for r in rows:
        def ms(k):
            return f"{1000 * r[k]:.0f} ms" if k in r else "–"
        print(f"| {r['binary']} | {r['size'].replace('x', ' × ')} m | {r.get('areas', '–')} | "
              f"{'yes' if r['ok'] else 'no: ' + r['refusal']} | {r['wall_s']:.2f} s | {r['peak_mb']:.0f} MB | "
              f"{r.get('time_per_m2_vs_60x40', float('nan')):.2f} | {r.get('memory_per_m2_vs_60x40', float('nan')):.2f} | "
              f"{ms('segment_source_s')} / {ms('segment_dest_s')} | {ms('prepare_s')} | {ms('features_s')} | "
              f"{ms('selection_s')} |")


if __name__ == "__main__":
    main()
