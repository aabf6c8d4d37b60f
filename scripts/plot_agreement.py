#!/usr/bin/env python3
"""Draws the agreement distributions of pairs of one building and of different buildings from
`areamatch eval --cross-buildings --out DIR` results (DIR/results.csv), one panel per DIR:

  plot_agreement.py OUT.svg THRESHOLD LABEL=DIR [LABEL=DIR ...]

Each panel is a histogram of MatchEvidence::agreement (bins of 0.02) for the same-building pairs
(green, drawn upwards) and the different-building pairs (red, downwards, on a square-root scale
so that a few stragglers among hundreds stay visible), with the threshold as a line and the
acceptance/rejection rates it gives. Standard library only."""
import csv, math, sys


def load(folder):
    same, different = [], []
    try:
        with open(folder + "/results.csv", newline="") as f:
            for row in csv.DictReader(f):
                if not row["agreement"]:
                    continue  # a pair that could not run, or no areas
                (different if row["different_buildings"] == "true" else same).append(float(row["agreement"]))
    except (OSError, KeyError) as e:
        raise SystemExit(f"cannot read {folder}/results.csv (from areamatch eval --cross-buildings): {e}")
    return same, different


def histogram(values, bins):
    counts = [0] * bins
    for v in values:
        counts[min(bins - 1, max(0, int(v * bins)))] += 1
    return counts


def main():
    if len(sys.argv) < 4:
        raise SystemExit(__doc__)
    out, threshold = sys.argv[1], float(sys.argv[2])
    panels = []
    for arg in sys.argv[3:]:
        label, _, folder = arg.partition("=")
        panels.append((label, *load(folder)))
    bins, W, PH, L, R, T = 50, 900, 170, 60, 20, 40
    H = T + PH * len(panels) + 40
    X = lambda v: L + v * (W - L - R)
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>',
           f'<text x="{L}" y="22" font-size="14">agreement under the best transform: same building (green, up) '
           f'vs different buildings (red, down, sqrt scale)</text>']
    for i, (label, same, different) in enumerate(panels):
        top = T + i * PH
        mid = top + PH * 0.5
        hs, hd = histogram(same, bins), histogram(different, bins)
        ms, md = max(hs + [1]), max(hd + [1])
        half = PH * 0.5 - 18
        for b in range(bins):
            x, w = X(b / bins), (W - L - R) / bins - 1
            if hs[b]:
                h = half * math.sqrt(hs[b] / ms)
                svg.append(f'<rect x="{x:.1f}" y="{mid - h:.1f}" width="{w:.1f}" height="{h:.1f}" fill="#2ca02c"/>')
            if hd[b]:
                h = half * math.sqrt(hd[b] / md)
                svg.append(f'<rect x="{x:.1f}" y="{mid:.1f}" width="{w:.1f}" height="{h:.1f}" fill="#d62728"/>')
        svg.append(f'<line x1="{L}" y1="{mid}" x2="{W - R}" y2="{mid}" stroke="#444"/>')
        tx = X(threshold)
        svg.append(f'<line x1="{tx:.1f}" y1="{top + 4}" x2="{tx:.1f}" y2="{top + PH - 4}" stroke="black" stroke-dasharray="4,3"/>')
        accepted = sum(v >= threshold for v in same)
        rejected = sum(v < threshold for v in different)
        rate = lambda a, n: f"{a}/{n} ({100.0 * a / n:.1f} %)" if n else "-"
        svg.append(f'<text x="{L + 4}" y="{top + 14}">{label}: one building accepted {rate(accepted, len(same))}, '
                   f'different buildings rejected {rate(rejected, len(different))}</text>')
    axis = T + PH * len(panels) + 4
    for k in range(11):
        x = X(k / 10)
        svg.append(f'<line x1="{x:.1f}" y1="{axis}" x2="{x:.1f}" y2="{axis + 5}" stroke="black"/>')
        svg.append(f'<text x="{x:.1f}" y="{axis + 18}" text-anchor="middle">{k / 10:.1f}</text>')
    svg.append(f'<text x="{X(threshold):.1f}" y="{axis + 32}" text-anchor="middle">threshold {threshold}</text>')
    svg.append("</svg>")
    with open(out, "w") as f:
        f.write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main()
