#!/usr/bin/env python3
"""The issue's three tables from the validation runs (run_validation.sh): for each scene and
transport (full, single scattering), from docs/bench/results/val_SCENE_{full,single}[_TAG].csv,
  1. pt:mis against the path tracer's best single technique (density, equiangular, product);
  2. in single scattering, bdpt:mis against pt:mis;
  3. the default (auto) against the best fixed method, and the geometric mean of auto / best
     over the four kinds the issue names (doorway, glass beam, fog room, g = 0.92 lamp).
Efficiency = 1 / (relative MSE x seconds). Prints markdown.

    python3 docs/bench/validation/tables.py [TAG] [--seeds]

--seeds: from the runs of several seeds (SEEDS="1 2 3" run_validation.sh:
val_SCENE_DEPTH[_TAG]_sSEED.csv), each method's efficiency is the geometric mean over the seeds."""
import csv
import glob
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, "..", "results")
SCENES = ["val_thin_lamp", "val_forward", "val_side_panel", "val_doorway", "val_glass_beam", "val_fog_room"]
KINDS = ["val_doorway", "val_glass_beam", "val_fog_room", "val_forward"]
SINGLE_PT = ["pt:density", "pt:equiangular", "pt:product"]


def load_file(path):
    eff = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            err, sec = float(r["rel_mse"]), float(r["seconds"])
            eff[r["method"]] = 1.0 / (err * sec) if err > 0 and sec > 0 else 0.0
    return eff


def load(scene, depth, tag, seeds=False):
    stem = os.path.join(RESULTS, "%s_%s%s" % (scene, depth, "_" + tag if tag else ""))
    if not seeds:
        return load_file(stem + ".csv") if os.path.exists(stem + ".csv") else None
    runs = [load_file(p) for p in sorted(glob.glob(stem + "_s*.csv"))]
    if not runs:
        return None
    methods = set.intersection(*(set(r) for r in runs))
    return {m: math.exp(sum(math.log(max(r[m], 1e-300)) for r in runs) / len(runs)) for m in methods}


def fmt(x):
    return "%.3g" % x


def main():
    args = [a for a in sys.argv[1:] if a != "--seeds"]
    seeds = "--seeds" in sys.argv[1:]
    tag = args[0] if args else ""
    runs = {(s, d): load(s, d, tag, seeds) for s in SCENES for d in ("full", "single")}

    print("**1. `pt --connect mis` against its best single technique** (target: within 1.25×)\n")
    print("| scene | transport | best single | its efficiency | pt:mis | best / pt:mis | |")
    print("|---|---|---|---|---|---|---|")
    for (s, d), e in runs.items():
        if not e or "pt:mis" not in e:
            continue
        best = max((m for m in SINGLE_PT if m in e), key=lambda m: e[m])
        r = e[best] / e["pt:mis"] if e["pt:mis"] > 0 else math.inf
        print("| %s | %s | %s | %s | %s | %.2f | %s |" % (s, d, best, fmt(e[best]), fmt(e["pt:mis"]), r,
                                                       "met" if r <= 1.25 else "**not met**"))

    print("\n**2. Single scattering: `bdpt --connect mis` against `pt --connect mis`** (target: within 1.5×)\n")
    print("| scene | pt:mis | bdpt:mis | pt:mis / bdpt:mis | |")
    print("|---|---|---|---|---|")
    for s in SCENES:
        e = runs[(s, "single")]
        if not e or "bdpt:mis" not in e:
            continue
        r = e["pt:mis"] / e["bdpt:mis"] if e["bdpt:mis"] > 0 else math.inf
        print("| %s | %s | %s | %.2f | %s |" % (s, fmt(e["pt:mis"]), fmt(e["bdpt:mis"]), r,
                                              "met" if r <= 1.5 else "**not met**"))

    print("\n**3. The default against the best fixed method** (target: within 1.25× everywhere; "
          "above 1 in the geometric mean over the four kinds)\n")
    print("| scene | transport | best fixed | its efficiency | auto | best / auto | |")
    print("|---|---|---|---|---|---|---|")
    logs = []
    for (s, d), e in runs.items():
        if not e or "auto" not in e:
            continue
        fixed = [m for m in e if m != "auto"]
        best = max(fixed, key=lambda m: e[m])
        r = e[best] / e["auto"] if e["auto"] > 0 else math.inf
        if s in KINDS:
            logs.append(math.log(e["auto"] / e[best]))
        print("| %s | %s | %s | %s | %s | %.2f | %s |" % (s, d, best, fmt(e[best]), fmt(e["auto"]), r,
                                                       "met" if r <= 1.25 else "**not met**"))
    if logs:
        g = math.exp(sum(logs) / len(logs))
        print("\nGeometric mean of auto / best fixed over the four kinds (%d cells): %.2f (%s)" %
              (len(logs), g, "met" if g > 1 else "**not met**"))


if __name__ == "__main__":
    main()
