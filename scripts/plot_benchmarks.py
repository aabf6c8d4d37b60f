#!/usr/bin/env python3
"""Turns Google Benchmark JSON output of areamatch_bench (its segment/ and match/ groups) into
  OUTDIR/benchmarks.csv   one line per benchmark: name, real time (ms), iterations, counters
  OUTDIR/scaling.svg      time against building size for the synthetic buildings (log-log)
  OUTDIR/benchmarks.md    the tables of docs/performance.md (segmentation per map, matching per pair)
Standard library only. Usage: plot_benchmarks.py OUTDIR segmentation.json matching.json ..."""
import csv, json, math, re, sys


def load(paths):
    rows, context = [], None
    for path in paths:
        try:
            with open(path) as f:
                data = json.load(f)
        except (OSError, ValueError) as e:
            raise SystemExit(f"cannot read benchmark results {path}: {e}")
        context = context or data.get("context", {})
        for b in data["benchmarks"]:
            if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
                continue
            scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]
            name = b.get("run_name", b["name"])
            counters = {k: v for k, v in b.items() if k.endswith("_ms") or k in ("areas", "cells", "hypotheses", "segments", "vertices")}
            rows.append({"name": name, "real_ms": b["real_time"] * scale, "iterations": b["iterations"], **counters})
    return rows, context


def write_csv(rows, path):
    keys = ["name", "real_ms", "iterations"] + sorted({k for r in rows for k in r} - {"name", "real_ms", "iterations"})
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow(r)


def write_svg(rows, context, path):
    series = {"segment": ("segmentation of one map", "#1f77b4"),
              "match": ("matching stage", "#d62728"),
              "pair": ("whole pair (segment both + match)", "#2ca02c")}
    points = {k: [] for k in series}
    for r in rows:
        m = re.fullmatch(r"(segment|match|pair)/synthetic_(\d+)m", r["name"])
        if m:
            points[m.group(1)].append((int(m.group(2)), r["real_ms"]))
    sides = sorted({s for pts in points.values() for s, _ in pts})
    times = [t for pts in points.values() for _, t in pts]
    if not sides:
        raise SystemExit("no synthetic_<N>m benchmarks in the input")
    W, H, L, R, T, B = 720, 440, 70, 250, 40, 50
    x0, x1 = math.log10(min(sides) / 1.2), math.log10(max(sides) * 1.2)
    y0, y1 = math.floor(math.log10(min(times))), math.ceil(math.log10(max(max(times), 15300)))
    X = lambda s: L + (math.log10(s) - x0) / (x1 - x0) * (W - L - R)
    Y = lambda t: H - B - (math.log10(t) - y0) / (y1 - y0) * (H - T - B)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>',
           f'<text x="{L}" y="22" font-size="14">areamatch time against building size (synthetic, 0.05 m cells)</text>']
    for e in range(y0, y1 + 1):
        y = Y(10 ** e)
        label = f"{10 ** e:g} ms" if e < 3 else f"{10 ** (e - 3):g} s"
        out.append(f'<line x1="{L}" y1="{y:.1f}" x2="{W - R}" y2="{y:.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{L - 6}" y="{y + 4:.1f}" text-anchor="end">{label}</text>')
    for s in sides:
        x = X(s)
        out.append(f'<line x1="{x:.1f}" y1="{T}" x2="{x:.1f}" y2="{H - B}" stroke="#eee"/>')
        out.append(f'<text x="{x:.1f}" y="{H - B + 16}" text-anchor="middle">{s} m</text>')
    out.append(f'<text x="{(L + W - R) / 2:.0f}" y="{H - 12}" text-anchor="middle">building side (square footprint)</text>')
    # The paper's average per pair (i7-6700): 15.3 s.
    y = Y(15300)
    out.append(f'<line x1="{L}" y1="{y:.1f}" x2="{W - R}" y2="{y:.1f}" stroke="#999" stroke-dasharray="6 4"/>')
    legend = [("paper: 15.3 s per pair (mean)", "#999", True)]
    for key, (label, colour) in series.items():
        pts = sorted(points[key])
        if not pts:
            continue
        polyline = " ".join(f"{X(s):.1f},{Y(t):.1f}" for s, t in pts)
        out.append(f'<polyline points="{polyline}" fill="none" stroke="{colour}" stroke-width="2"/>')
        out += [f'<circle cx="{X(s):.1f}" cy="{Y(t):.1f}" r="3" fill="{colour}"/>' for s, t in pts]
        legend.append((label, colour, False))
    for i, (label, colour, dashed) in enumerate(legend):
        y = T + 10 + 20 * i
        dash = ' stroke-dasharray="6 4"' if dashed else ""
        out.append(f'<line x1="{W - R + 12}" y1="{y}" x2="{W - R + 36}" y2="{y}" stroke="{colour}" stroke-width="2"{dash}/>')
        out.append(f'<text x="{W - R + 42}" y="{y + 4}">{label}</text>')
    machine = f'{context.get("num_cpus", "?")} CPUs at {context.get("mhz_per_cpu", "?")} MHz, {context.get("date", "")}'
    out.append(f'<text x="{W - R + 12}" y="{H - B}" fill="#666" font-size="10">{machine}</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def write_markdown(rows, path):
    by_name = {r["name"]: r for r in rows}
    out = ["## Segmentation (map already loaded)", "", "| map | cells | areas | ms |", "|---|---:|---:|---:|"]
    for r in rows:
        if r["name"].startswith("segment/"):
            out.append(f'| {r["name"][8:]} | {int(r.get("cells", 0))} | {int(r.get("areas", 0))} | {r["real_ms"]:.1f} |')
    builds = [r for r in rows if r["name"].startswith("voronoi/")]
    if builds:
        out += ["", "## Voronoi builder (the segmenter's input, already traced)", "",
                "| map | segments | ours ms | Boost's construct_voronoi ms |", "|---|---:|---:|---:|"]
        for r in builds:
            name = r["name"][8:]
            boost = by_name.get("voronoi_boost/" + name)
            out.append(f'| {name} | {int(r.get("segments", 0))} | {r["real_ms"]:.1f} | '
                       + (f'{boost["real_ms"]:.1f} |' if boost else "– |"))
    out += ["", "## Matching", "",
            "| pair | areas | hypotheses | match ms | features | hypotheses | clustering | selection | whole pair ms |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        if not r["name"].startswith("match/"):
            continue
        name = r["name"][6:]
        whole = by_name.get("pair/" + name)
        out.append(f'| {name} | {int(r.get("areas", 0))} | {int(r.get("hypotheses", 0))} | {r["real_ms"]:.1f} | '
                   f'{r.get("features_ms", 0):.1f} | {r.get("hypotheses_ms", 0):.1f} | {r.get("clustering_ms", 0):.1f} | '
                   f'{r.get("selection_ms", 0):.1f} | {whole["real_ms"]:.1f} |' if whole else "")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    outdir, inputs = sys.argv[1], sys.argv[2:]
    rows, context = load(inputs)
    write_csv(rows, f"{outdir}/benchmarks.csv")
    write_svg(rows, context, f"{outdir}/scaling.svg")
    write_markdown(rows, f"{outdir}/benchmarks.md")
    print(f"wrote {outdir}/benchmarks.csv ({len(rows)} benchmarks), benchmarks.md and scaling.svg")


if __name__ == "__main__":
    main()
