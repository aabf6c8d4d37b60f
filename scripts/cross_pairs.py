#!/usr/bin/env python3
"""Writes a manifest of map pairs that must not match (`different_buildings`), for calibrating
and checking the accept/reject decision.

cross_pairs.py OUT.json --reverse MANIFEST
    the reverse direction of what `areamatch eval MANIFEST --cross-buildings` runs: every two
    maps of different buildings (maps joined by a pair of the manifest are one building), the
    later map as source and the earlier one as destination. With `--cross-buildings` itself this
    gives both directions, the matcher being asymmetric (the source is placed on the destination).
cross_pairs.py OUT.json --between MANIFEST_A MANIFEST_B [--only-b NAME,...] [--both]
    every map of A as source against every map of B (or the named ones: paths relative to B's
    folder, without extension) as destination, and B onto A with --both.

Maps are listed in the order of their first appearance, as `areamatch::cross_building_pairs`
lists them; a map keeps the resolution and door width of the first pair that names it; a pair
gets a door width only when both maps have the same one; reflection is allowed. Paths are
written absolute, so OUT.json may live anywhere. Standard library only.
"""
import argparse, json, os, sys


def load_maps(path):
    """The manifest's maps (path, resolution, door width, name) and a building id for each."""
    with open(path) as f:
        manifest = json.load(f)
    folder = os.path.dirname(os.path.abspath(path))
    maps, index, parent = [], {}, []

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    def add(rel, resolution, door):
        full = os.path.normpath(os.path.join(folder, rel))
        if full not in index:
            index[full] = len(maps)
            parent.append(len(maps))
            name = os.path.splitext(os.path.relpath(full, folder))[0]
            maps.append({"path": full, "resolution": resolution, "door_width_m": door, "name": name})
        return index[full]

    for pair in manifest.get("pairs", []):
        if pair.get("different_buildings"):
            continue
        door = pair.get("door_width_m")
        a = add(pair["source"], pair.get("source_resolution"), door)
        b = add(pair["destination"], pair.get("destination_resolution"), door)
        parent[find(a)] = find(b)
    if not maps:
        raise SystemExit("%s: no pairs of one building" % path)
    return maps, [find(i) for i in range(len(maps))]


def pair(source, destination):
    p = {"name": source["name"] + " x " + destination["name"], "kind": "different_buildings",
         "source": source["path"], "destination": destination["path"],
         "allow_reflection": True, "different_buildings": True}
    if source["resolution"] is not None:
        p["source_resolution"] = source["resolution"]
    if destination["resolution"] is not None:
        p["destination_resolution"] = destination["resolution"]
    if source["door_width_m"] is not None and source["door_width_m"] == destination["door_width_m"]:
        p["door_width_m"] = source["door_width_m"]
    return p


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--reverse", metavar="MANIFEST")
    ap.add_argument("--between", nargs=2, metavar=("MANIFEST_A", "MANIFEST_B"))
    ap.add_argument("--only-b", metavar="NAMES", help="with --between: only these maps of B (comma-separated)")
    ap.add_argument("--both", action="store_true", help="with --between: also B onto A")
    args = ap.parse_args()
    if bool(args.reverse) == bool(args.between):
        ap.error("give exactly one of --reverse and --between")
    pairs = []
    if args.reverse:
        maps, building = load_maps(args.reverse)
        for i in range(len(maps)):
            for j in range(i + 1, len(maps)):
                if building[i] != building[j]:
                    pairs.append(pair(maps[j], maps[i]))
    else:
        a, _ = load_maps(args.between[0])
        b, _ = load_maps(args.between[1])
        if args.only_b:
            names = args.only_b.split(",")
            unknown = [n for n in names if n not in {m["name"] for m in b}]
            if unknown:
                raise SystemExit("--only-b: %s: no such map in %s" % (unknown[0], args.between[1]))
            b = [m for m in b if m["name"] in names]
        shared = {m["path"] for m in a} & {m["path"] for m in b}
        if shared:
            raise SystemExit("the manifests share maps (%s): they are not different buildings" % sorted(shared)[0])
        pairs = [pair(s, d) for s in a for d in b]
        if args.both:
            pairs += [pair(s, d) for s in b for d in a]
    out = {"description": "pairs of maps of different buildings (scripts/cross_pairs.py)",
           "correct_if": {"max_rotation_error_deg": 3.0, "max_mean_displacement_m": 1.0},
           "pairs": pairs}
    with open(args.out, "w") as f:
        json.dump(out, f, indent=1)
    print("%s: %d pairs" % (args.out, len(pairs)))


if __name__ == "__main__":
    sys.exit(main())
