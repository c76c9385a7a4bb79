#!/usr/bin/env python3
"""Efficiency ratios from the CSVs that `brume bench` writes (docs/bench/results/*.csv, as
docs/bench/run_all.sh leaves them): for every scene and method, the efficiency 1/(error ×
seconds) divided by that of a base method (default pt:mis) at the same budget, printed as a
markdown table for docs/results.md. Each cell gives the ratio at the largest budget and, in
brackets, the range over all budgets.

    python3 docs/bench/efficiency_table.py [--base METHOD] [--rmse] CSV...

--rmse measures error by RMSE² instead of relative MSE (relative MSE weighs dark pixels
heavily; where the base method misses light entirely, both are worth reading)."""
import argparse
import csv
import os
from collections import defaultdict


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv", nargs="+")
    ap.add_argument("--base", default="pt:mis")
    ap.add_argument("--rmse", action="store_true")
    args = ap.parse_args()

    methods = []
    rows = []
    for path in args.csv:
        eff = defaultdict(dict)  # method -> budget -> efficiency
        scene = os.path.splitext(os.path.basename(path))[0]
        with open(path) as f:
            for r in csv.DictReader(f):
                err = float(r["rmse"]) ** 2 if args.rmse else float(r["rel_mse"])
                seconds = float(r["seconds"])
                if err > 0 and seconds > 0:
                    eff[r["method"]][float(r["budget_s"])] = 1.0 / (err * seconds)
                scene = r["scene"]
                if r["method"] not in methods:
                    methods.append(r["method"])
        rows.append((scene, eff))

    shown = [m for m in methods if m != args.base]
    measure = "RMSE²" if args.rmse else "relative MSE"
    print(f"| scene ({measure}; efficiency / `{args.base}`) | " + " | ".join(f"`{m}`" for m in shown) + " |")
    print("|---" * (len(shown) + 1) + "|")
    for scene, eff in rows:
        base = eff.get(args.base, {})
        cells = []
        for m in shown:
            ratios = {b: e / base[b] for b, e in eff.get(m, {}).items() if b in base}
            if not ratios:
                cells.append("-")
                continue
            last = ratios[max(ratios)]
            lo, hi = min(ratios.values()), max(ratios.values())
            cells.append(f"{last:.2g} ({lo:.2g}–{hi:.2g})")
        print(f"| `{scene}` | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
