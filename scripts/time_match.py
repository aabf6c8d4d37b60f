#!/usr/bin/env python3
"""Times `areamatch match SOURCE DEST --json` (the program as a user runs it: load, segment both,
match; two threads by default) on the pairs of ../shared/pairs.json, several builds interleaved
so that they see the same machine.

time_match.py ROUNDS BINARY [BINARY...] [-- EXTRA MATCH ARGS]

Per binary: the median over pairs of each pair's median `timings.total_s`, `timings.match_s` and
the process's wall time. The VMs this runs on vary by up to ~30 % from hour to hour: compare
builds within one run only. Standard library only.
"""
import json, os, statistics, subprocess, sys, time

def main():
    args = sys.argv[1:]
    extra = []
    if "--" in args:
        extra = args[args.index("--") + 1:]
        args = args[:args.index("--")]
    if len(args) < 2:
        sys.exit(__doc__)
    rounds, binaries = int(args[0]), args[1:]
    shared = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared")
    pairs = json.load(open(os.path.join(shared, "pairs.json")))["pairs"]
    runs = {b: {"total": {}, "match": {}, "wall": {}} for b in binaries}
    for r in range(rounds):
        for p in pairs:
            for b in (binaries if r % 2 == 0 else binaries[::-1]):
                cmd = [b, "match", os.path.join(shared, p["source"]), os.path.join(shared, p["destination"]), "--json"] + extra
                if p.get("door_width_m"):
                    cmd += ["--door-width", str(p["door_width_m"])]
                start = time.perf_counter()
                out = subprocess.run(cmd, capture_output=True, text=True)
                wall = time.perf_counter() - start
                timings = json.loads(out.stdout)["timings"]
                for key, value in (("total", timings["total_s"]), ("match", timings["match_s"]), ("wall", wall)):
                    runs[b][key].setdefault(p["name"], []).append(value)
    for b in binaries:
        med = lambda per_pair: 1000 * statistics.median(statistics.median(v) for v in per_pair.values())
        print("%s: total_s %.1f ms, match_s %.1f ms, process wall %.1f ms (medians over %d pairs, %d rounds)" % (
            b, med(runs[b]["total"]), med(runs[b]["match"]), med(runs[b]["wall"]), len(pairs), rounds))

if __name__ == "__main__":
    main()
