#!/usr/bin/env python3
"""Plots how merging grows with the number of maps, from areamatch_bench's merge/ JSON output.

plot_merge.py MERGE.json OUT.svg

Draws, against N (the merge/synthetic/<N> benchmarks), the merge time (real time, median when
repeated) split into matching, pose fit and fusion, and the N preparations beside it; prints the
table. Standard library only."""
import json, re, sys


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    data = json.load(open(sys.argv[1]))
    rows = {}
    repeated = any(b.get("run_type") == "aggregate" for b in data["benchmarks"])
    for b in data["benchmarks"]:
        if repeated and b.get("aggregate_name") != "median":
            continue
        name = b.get("run_name", b["name"])
        if not name.startswith("merge/synthetic/") or "threads" in name:
            if name.startswith("merge/"):
                print("%-20s %8.1f ms (prepare %.0f ms, matching %.0f, refine %.0f, fit %.1f, fuse %.0f)" % (
                    name, b["real_time"], b["prepare_ms"], b["matching_ms"], b.get("refine_ms", 0.0), b["fit_ms"], b["fuse_ms"]))
            continue
        n = int(re.match(r"merge/synthetic/(\d+)", name).group(1))
        rows[n] = b
    if not rows:
        print("plot_merge.py: no merge/synthetic/<N> benchmarks in " + sys.argv[1], file=sys.stderr)
        return 2
    ns = sorted(rows)
    print("%4s %10s %10s %8s %8s %8s %10s" % ("N", "merge_ms", "matching", "refine", "fit", "fuse", "prepare"))
    for n in ns:
        b = rows[n]
        print("%4d %10.1f %10.1f %8.1f %8.2f %8.1f %10.1f" % (n, b["real_time"], b["matching_ms"], b.get("refine_ms", 0.0), b["fit_ms"],
                                                          b["fuse_ms"], b["prepare_ms"]))
    width, height, left, bottom, top, right = 560, 360, 70, 50, 30, 150
    x_max = max(ns)
    y_max = max(rows[n]["real_time"] + rows[n]["prepare_ms"] for n in ns) * 1.1
    X = lambda n: left + (width - left - right) * n / x_max
    Y = lambda ms: height - bottom - (height - bottom - top) * ms / y_max
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">' % (width, height),
           '<rect width="100%" height="100%" fill="white"/>',
           '<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="black"/>' % (left, height - bottom, width - right, height - bottom),
           '<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="black"/>' % (left, top, left, height - bottom)]
    step = 10 ** len(str(int(y_max))) / 10
    while y_max / step > 8: step *= 2
    tick = 0.0
    while tick <= y_max:
        out.append('<text x="%d" y="%.1f" text-anchor="end">%g</text>' % (left - 6, Y(tick) + 4, tick))
        out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (left, Y(tick), width - right, Y(tick)))
        tick += step
    for n in ns:
        out.append('<text x="%.1f" y="%d" text-anchor="middle">%d</text>' % (X(n), height - bottom + 16, n))
    out.append('<text x="%d" y="%d" text-anchor="middle">maps merged (N)</text>' % ((left + width - right) / 2, height - 12))
    out.append('<text x="16" y="%d" transform="rotate(-90 16 %d)" text-anchor="middle">ms</text>' % ((top + height - bottom) / 2, (top + height - bottom) / 2))
    series = [("merge (all)", lambda b: b["real_time"], "#c0392b"), ("matching", lambda b: b["matching_ms"], "#2874a6"),
              ("refinement", lambda b: b.get("refine_ms", 0.0), "#8e44ad"), ("fusion", lambda b: b["fuse_ms"], "#27ae60"),
              ("N preparations", lambda b: b["prepare_ms"], "#7f8c8d")]
    for i, (label, value, colour) in enumerate(series):
        points = " ".join("%.1f,%.1f" % (X(n), Y(value(rows[n]))) for n in ns)
        out.append('<polyline points="%s" fill="none" stroke="%s" stroke-width="2"/>' % (points, colour))
        for n in ns:
            out.append('<circle cx="%.1f" cy="%.1f" r="3" fill="%s"/>' % (X(n), Y(value(rows[n])), colour))
        out.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="%s" stroke-width="2"/>' % (width - right + 12, top + 10 + 18 * i, width - right + 32, top + 10 + 18 * i, colour))
        out.append('<text x="%d" y="%d">%s</text>' % (width - right + 38, top + 14 + 18 * i, label))
    out.append("</svg>")
    open(sys.argv[2], "w").write("\n".join(out) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
