#!/usr/bin/env python3
"""How matching cost grows with the floor (issue 44): generated buildings from 30 x 20 m to
400 x 300 m (`areamatch generate --width W --height H --seed 7`, the 400 x 300 m one unturned),
each robot map matched onto its layout by `areamatch match --json` in a fresh process, ROUNDS
times (median). Per size: areas, wall time, peak memory (/usr/bin/time), the stages' times from
the JSON, and time and memory per square metre relative to 60 x 40 m. With two binaries, each
round runs both, alternating, so that they see the same machine.

  scripts/growth.py OUTDIR [--rounds N] [--sizes 30x20,60x40,...] BINARY [BINARY2]

Writes OUTDIR/growth.csv, OUTDIR/growth.svg (time and peak memory per square metre against the
footprint, log-log, with the issue's targets: 1.5 x the 60 x 40 m time per m², 250 MB at
240 x 160 m and 1 GB at 400 x 300 m) and prints a markdown table. Refusals (too many areas, a
grid too large) are rows with the reason, not failures of the script.
"""
import argparse
import csv
import json
import math
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


def write_svg(rows, path):
    """Two panels, log-log against the footprint: wall time per m² and peak memory per m²."""
    binaries = list(dict.fromkeys(r["binary"] for r in rows))
    colours = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd"]
    W, H, L, T, B, gap = 940, 420, 70, 60, 50, 90
    panel = (W - L - 30 - gap) / 2
    m2s = [r["m2"] for r in rows]
    x0, x1 = math.log10(min(m2s) / 1.3), math.log10(max(m2s) * 1.3)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>',
           f'<text x="{L}" y="22" font-size="14">areamatch match on generated floors: cost per square metre against the floor '
           f'(one process each, median)</text>']
    base = {r["binary"]: r for r in rows if r["size"] == "60x40" and r["ok"]}
    panels = [("wall time per m² (µs)", lambda r: 1e6 * r["wall_s"] / r["m2"]),
              ("peak memory per m² (KB)", lambda r: 1024.0 * r["peak_mb"] / r["m2"])]
    for p, (title, value) in enumerate(panels):
        left = L + p * (panel + gap)
        values = [value(r) for r in rows]
        targets = []
        if p == 0:
            for b, r in base.items():
                targets.append((f"1.5 x {b or 'its'} 60 x 40 m", None, 1.5 * value(r)))
        else:
            targets = [("250 MB at 240 x 160 m", 240 * 160, 1024.0 * 250 / (240 * 160)),
                       ("1 GB at 400 x 300 m", 400 * 300, 1024.0 * 1024 / (400 * 300))]
        everything = values + [t[2] for t in targets]
        y0, y1 = math.log10(min(everything) / 1.4), math.log10(max(everything) * 1.4)
        X = lambda m2: left + (math.log10(m2) - x0) / (x1 - x0) * panel
        Y = lambda v: H - B - (math.log10(v) - y0) / (y1 - y0) * (H - T - B)
        out.append(f'<text x="{left}" y="{T - 12}" font-size="13">{title}</text>')
        out.append(f'<rect x="{left}" y="{T}" width="{panel:.0f}" height="{H - T - B}" fill="none" stroke="#ccc"/>')
        for e in range(math.floor(y0), math.ceil(y1) + 1):
            for m in (1, 2, 5):
                v = m * 10 ** e
                if not (y0 <= math.log10(v) <= y1):
                    continue
                out.append(f'<line x1="{left}" y1="{Y(v):.1f}" x2="{left + panel:.0f}" y2="{Y(v):.1f}" stroke="#eee"/>')
                out.append(f'<text x="{left - 5}" y="{Y(v) + 4:.1f}" text-anchor="end" font-size="10">{v:g}</text>')
        for size in dict.fromkeys(r["size"] for r in rows):
            m2 = next(r["m2"] for r in rows if r["size"] == size)
            out.append(f'<text x="{X(m2):.1f}" y="{H - B + 15}" text-anchor="middle" font-size="10">{size.replace("x", "×")}</text>')
        out.append(f'<text x="{left + panel / 2:.0f}" y="{H - 14}" text-anchor="middle">floor (m), log of its area</text>')
        for k, (label, at, v) in enumerate(targets):
            if at is None:
                out.append(f'<line x1="{left}" y1="{Y(v):.1f}" x2="{left + panel:.0f}" y2="{Y(v):.1f}" stroke="#999" stroke-dasharray="6 4"/>')
            else:
                out.append(f'<path d="M{X(at) - 6:.1f},{Y(v):.1f} h12" stroke="#999" stroke-width="3"/>')
            tx, ty = (left + panel - 4, Y(v) - 4) if at is None else (X(at) - 10, Y(v) + 4)
            out.append(f'<text x="{tx:.0f}" y="{ty:.1f}" text-anchor="end" fill="#777" font-size="10">{label}</text>')
        for i, b in enumerate(binaries):
            pts = sorted((r["m2"], value(r), r["ok"]) for r in rows if r["binary"] == b)
            colour = colours[i % len(colours)]
            line = " ".join(f"{X(m):.1f},{Y(v):.1f}" for m, v, _ in pts)
            out.append(f'<polyline points="{line}" fill="none" stroke="{colour}" stroke-width="2"/>')
            for m, v, ok in pts:  # hollow: refused or rejected
                out.append(f'<circle cx="{X(m):.1f}" cy="{Y(v):.1f}" r="4" fill="{colour if ok else "white"}" stroke="{colour}"/>')
            if p == 1:
                y = T + 14 + 18 * i
                out.append(f'<line x1="{left + 10:.0f}" y1="{y}" x2="{left + 34:.0f}" y2="{y}" stroke="{colour}" stroke-width="2"/>')
                out.append(f'<text x="{left + 40:.0f}" y="{y + 4}">{b or "binary"}</text>')
    out.append(f'<text x="{L}" y="{H - 2}" fill="#666" font-size="10">hollow: refused or rejected</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


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
    write_svg(rows, os.path.join(args.outdir, "growth.svg"))
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
