#!/usr/bin/env python3
"""auto against the fixed methods, from the CSVs and bench outputs that docs/bench/run_all.sh
leaves in docs/bench/results/: per scene and budget, auto's efficiency 1/(relative MSE ×
seconds) over that of the best fixed method in the same run, which method that was, and the
allocation auto chose (from NAME.txt). Prints a markdown table for docs/results.md.

    python3 docs/bench/auto_table.py docs/bench/results/*.csv"""
import csv
import os
import re
import sys
from collections import defaultdict


def main():
    print("| scene | budget (s) | auto / best fixed | best fixed | auto / bdpt:mis | auto / pt:mis | auto's allocation |")
    print("|---|---|---|---|---|---|---|")
    ratios = []
    for path in sys.argv[1:]:
        eff = defaultdict(dict)  # budget -> method -> efficiency
        scene = os.path.splitext(os.path.basename(path))[0]
        with open(path) as f:
            for r in csv.DictReader(f):
                err, sec = float(r["rel_mse"]), float(r["seconds"])
                if err > 0 and sec > 0:
                    eff[float(r["budget_s"])][r["method"]] = 1.0 / (err * sec)
        choices = []
        txt = os.path.splitext(path)[0] + ".txt"
        if os.path.exists(txt):
            choices = re.findall(r"allocation: (.*?) \(", open(txt).read())
        for i, budget in enumerate(sorted(eff)):
            e = eff[budget]
            if "auto" not in e:
                continue
            fixed = {m: v for m, v in e.items() if m != "auto"}
            best = max(fixed, key=fixed.get)
            ratio = e["auto"] / fixed[best]
            ratios.append(ratio)
            choice = choices[i] if i < len(choices) else "?"
            rel = lambda m: "%.2f" % (e["auto"] / e[m]) if m in e else "-"
            print("| `%s` | %g | %.2f | `%s` | %s | %s | `%s` |" % (scene, budget, ratio, best, rel("bdpt:mis"),
                                                                 rel("pt:mis"), choice))
    if ratios:
        within = sum(1 for r in ratios if r >= 0.8)
        print("\n%d of %d cells within 1.25x of the best fixed method (ratio >= 0.8); geometric mean %.2f" %
              (within, len(ratios), pow(2.0, sum(__import__("math").log2(r) for r in ratios) / len(ratios))))


if __name__ == "__main__":
    main()
