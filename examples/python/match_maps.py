#!/usr/bin/env python3
"""Match two maps and show the match.

    python3 match_maps.py robot.yaml layout.yaml [--allow-reflection] [--out match.png]

Prints the transform, then draws the source map's walls over the destination map with matplotlib
when it is installed (into --out, or a window), else writes the library's own picture.
Without arguments it makes a synthetic building and a turned robot map of it and matches those.
"""

import argparse
import sys

import numpy as np

import areamatch


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("source", nargs="?", help="map to place (YAML, PNG or PGM)")
    parser.add_argument("dest", nargs="?", help="map to place it on")
    parser.add_argument("--allow-reflection", action="store_true")
    parser.add_argument("--door-width", type=float)
    parser.add_argument("--out", help="picture file (PNG); default: a window, or match.png without matplotlib")
    args = parser.parse_args(argv)

    if args.source and args.dest:
        source, dest = areamatch.load_map(args.source), areamatch.load_map(args.dest)
    elif args.source or args.dest:
        parser.error("give both maps, or none for the synthetic example")
    else:
        building = areamatch.synthetic.generate_building(3)
        robot = areamatch.synthetic.make_robot_map(building, 4, rotation_rad=0.6, translation_m=(1.0, -1.5),
                                                   explored_fraction=0.6, wall_noise_m=0.02)
        source, dest = robot.map, building.layout

    result = areamatch.match(source, dest, allow_reflection=args.allow_reflection, door_width_m=args.door_width)
    print(f"{'matched' if result.ok else 'no match'}: rotation {result.rotation_deg:.2f} deg, "
          f"translation ({result.translation_m[0]:.3f}, {result.translation_m[1]:.3f}) m, "
          f"p_correct {result.p_correct:.3f}, {len(result.matched_areas)} matched areas")
    if not result.ok:
        print(f"reason: {result.reason}")

    try:
        import matplotlib
        if args.out:
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        out = args.out or "match.png"
        result.picture().save(out)
        print(f"matplotlib not installed: wrote the library's picture to {out}")
        return 0 if result.ok else 1

    # The destination in world metres, the source's occupied cells carried over by the result.
    d = dest
    extent = [d.origin[0], d.origin[0] + d.width * d.resolution, d.origin[1], d.origin[1] + d.height * d.resolution]
    fig, ax = plt.subplots(figsize=(8, 8))
    ax.imshow(d.to_image(), cmap="gray", extent=extent, vmin=0, vmax=255)  # rows top to bottom = y down
    # Walls: occupied cells next to free space (not the solid outside some maps draw).
    cells = np.pad(source.cells, 1, constant_values=areamatch.UNKNOWN)
    free = cells == areamatch.FREE
    near_free = free[:-2, 1:-1] | free[2:, 1:-1] | free[1:-1, :-2] | free[1:-1, 2:]
    rows, cols = np.nonzero((source.cells == areamatch.OCCUPIED) & near_free)
    pixels = np.stack([cols, rows, np.ones_like(cols)]).astype(float)
    world = result.T_dest_source @ source.world_from_pixel() @ pixels
    ax.scatter(world[0], world[1], s=0.2, c="tab:red", label="source walls, placed")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(loc="upper right", markerscale=20)
    ax.set_title(f"rotation {result.rotation_deg:.1f} deg, p_correct {result.p_correct:.2f}")
    if args.out:
        fig.savefig(args.out, dpi=120)
        print(f"wrote {args.out}")
    else:
        plt.show()
    return 0 if result.ok else 1


if __name__ == "__main__":
    sys.exit(main())
