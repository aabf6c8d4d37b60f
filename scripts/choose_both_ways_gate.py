#!/usr/bin/env python3
"""Chooses the agreement gate's both-ways thresholds (`DecisionParams::gate_both_ways_min_occupied`
and `gate_both_ways_min_margin`, docs/evaluation.md "Where the walls agree both ways") and measures
the choice on simulated SLAM maps, each plan left out in turn.

choose_both_ways_gate.py --predictions PRED.csv --calibration CAL_DIR --simulated SIM.csv [SIM.csv ...]

PRED.csv     `areamatch calibrate CAL_DIR/*/results.csv --predictions PRED.csv`: each calibration row's
             cross-validated p_correct (the model never saw the row's buildings)
CAL_DIR      the folder of `scripts/calibration_data.sh` (its */results.csv: the rows' signals)
SIM.csv      `areamatch eval` results of simulated SLAM maps onto their plans and onto other plans
             (`scripts/calibration_data.sh` writes them to CAL_DIR/simulated/*/results.csv); their
             p_correct is the shipped model's, which never trained on them

Generated and simulated rows choose; real buildings' rows are only counted (the thresholds act
where the walls agree both ways, and the real rows there are checked to keep their verdicts). A
choice: the fewest right answers refused with no wrong answer accepted (a symmetric building's
turned copy is a wrong answer too), ties to the stricter thresholds. The simulated rows are then
judged plan by plan, each by thresholds chosen without its plan's rows. Standard library only.
"""
import argparse, collections, csv, glob, os, sys

# DecisionParams' other thresholds (the shipped ones).
MIN_SCORE, ACCEPT_P, MIN_AGREEMENT, MAX_LOWER_WALLS, MIN_OVERLAP = 0.1, 0.85, 0.835, 0.7, 100.0
OCCUPIED_GRID = [2.0, 0.95, 0.9, 0.85, 0.8, 0.75, 0.7]          # strict to lenient (above 1: off)
MARGIN_GRID = [0.05, 0.02, 0.01, 0.007, 0.005, 0.002, 0.0]


def number(row, key):
    try:
        return float(row[key])
    except (KeyError, ValueError):
        return float("nan")


def signals(row, p, right, tag, plans, own=None):
    forward, reverse = number(row, "forward_wall_agreement"), number(row, "reverse_wall_agreement")
    lower = min(forward, reverse) if forward == forward and reverse == reverse else 0.0
    return dict(name=row["name"], p=p, right=right, tag=tag, plans=plans, own=own, agreement=number(row, "agreement"),
                lower=lower, overlap=number(row, "overlap_m2"), score=number(row, "score"), occupied=number(row, "occupied_wall_agreement"),
                margin=number(row, "margin"))


def accepts(r, occupied, margin):
    if r["score"] < MIN_SCORE:
        return False
    if r["p"] >= ACCEPT_P:
        return True
    if not (r["agreement"] >= MIN_AGREEMENT and r["overlap"] >= MIN_OVERLAP):
        return False
    return r["lower"] <= MAX_LOWER_WALLS or (r["occupied"] >= occupied and r["margin"] >= margin)


def counts(rows, occupied, margin):
    right = sum(1 for r in rows if r["right"])
    refused = sum(1 for r in rows if r["right"] and not accepts(r, occupied, margin))
    wrong_accepted = sum(1 for r in rows if not r["right"] and accepts(r, occupied, margin))
    return right, refused, wrong_accepted


def choose(rows):
    best = None
    for occupied in OCCUPIED_GRID:
        for margin in MARGIN_GRID:
            _, refused, wrong_accepted = counts(rows, occupied, margin)
            key = (wrong_accepted > 0, refused, wrong_accepted)
            if best is None or key < best[0]:  # grids run strict to lenient: a tie keeps the stricter
                best = (key, occupied, margin)
    return best[1], best[2]


def plan_of(path):
    return os.path.splitext(os.path.basename(path))[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--predictions", required=True)
    ap.add_argument("--calibration", required=True)
    ap.add_argument("--simulated", nargs="+", required=True)
    a = ap.parse_args()

    # Calibration rows, in calibrate's order per (name, source, destination), with their cross-validated p.
    predicted = collections.defaultdict(list)
    for p in csv.DictReader(open(a.predictions)):
        predicted[(p["name"], os.path.realpath(p["source"]), os.path.realpath(p["destination"]))].append(p)
    rows = []
    for path in sorted(glob.glob(os.path.join(a.calibration, "*", "results.csv"))):
        for r in csv.DictReader(open(path)):
            key = (r["name"], os.path.realpath(r["source"]), os.path.realpath(r["destination"]))
            if not predicted[key]:
                continue  # ambiguous, failed or without ground truth: calibrate left it out
            p = predicted[key].pop(0)
            generated = p["source_building"].startswith("pair_") or p["dest_building"].startswith("pair_")
            rows.append(signals(r, float(p["p_correct_cv"]), p["right"] == "true", "generated" if generated else "real", set()))
    # Simulated rows: a simulated map joins its plan (the destination of its own pair; the folder
    # it was simulated into names the plan for pairs onto other plans).
    for path in a.simulated:
        for r in csv.DictReader(open(path)):
            if r["failure"] or r["ambiguous"] == "true":
                continue
            different = r["different_buildings"] == "true"
            if not different and r["transform_correct"] == "":
                continue
            own = os.path.basename(os.path.dirname(r["source"])).replace("_mirrored", "") if different else plan_of(r["destination"])
            plans = {own, plan_of(r["destination"])}
            rows.append(signals(r, number(r, "p_correct"), not different and r["transform_correct"] == "true",
                                "simulated", plans, own))
    choosing = [r for r in rows if r["tag"] != "real"]
    occupied, margin = choose(choosing)
    print("rows: %s" % dict(collections.Counter(r["tag"] for r in rows)))
    print("chosen on every generated and simulated row: gate_both_ways_min_occupied %g, gate_both_ways_min_margin %g"
          % (occupied, margin))
    for tag in ("real", "generated", "simulated"):
        part = [r for r in rows if r["tag"] == tag]
        for name, (o, m) in (("off", (2.0, 0.0)), ("chosen", (occupied, margin))):
            right, refused, wrong_accepted = counts(part, o, m)
            wrong = len(part) - right
            print("  %-9s both-ways part %-6s: right %d, refused %d; wrong %d, accepted %d" % (tag, name, right, refused, wrong, wrong_accepted))

    print("\nsimulated maps, each plan's rows judged by thresholds chosen without them:")
    print("plan | chosen occupied, margin | right answers | right and accepted | wrong transforms | accepted | onto other plans | accepted")
    total = collections.Counter()
    simulated = [r for r in rows if r["tag"] == "simulated"]
    for plan in sorted(set(r["own"] for r in simulated)):
        o, m = choose([r for r in choosing if plan not in r["plans"]])
        own = [r for r in simulated if r["plans"] == {plan}]
        other = [r for r in simulated if r["own"] == plan and len(r["plans"]) > 1]  # the simulated map's plan
        right = sum(r["right"] for r in own)
        c = dict(right=right, accepted=sum(1 for r in own if r["right"] and accepts(r, o, m)),
                 wrong=len(own) - right, wrong_accepted=sum(1 for r in own if not r["right"] and accepts(r, o, m)),
                 other=len(other), other_accepted=sum(1 for r in other if accepts(r, o, m)))
        total.update(c)
        print("%s | %g, %g | %d | %d | %d | %d | %d | %d" % (plan, o, m, c["right"], c["accepted"], c["wrong"], c["wrong_accepted"],
                                                          c["other"], c["other_accepted"]))
    print("total | | %d | %d | %d | %d | %d | %d" % (total["right"], total["accepted"], total["wrong"], total["wrong_accepted"],
                                                 total["other"], total["other_accepted"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
