#!/usr/bin/env bash
# The figures of docs/results.md: `brume bench` with auto and the six fixed methods (budgets
# 1, 2, 4 s at 160x120 unless BUDGETS says otherwise) on every bundled scene and on the five
# scenes of the BDPT tests, then each chart (PNG, SVG), results table and bench output (which
# names auto's choices) copied to docs/bench/results/. About 35 minutes on 2 cores at the
# default budgets; run it on an otherwise idle machine (bench warns when its threads were
# starved). docs/bench/auto_table.py turns the CSVs into the table of auto against the best
# fixed method.
#   bash docs/bench/run_all.sh [WORKDIR]      (default build/bench; references are cached there,
#                                             for as long as brume is not rebuilt)
#   BUDGETS=4,16 METHODS=auto,pt:mis bash docs/bench/run_all.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
work=${1:-build/bench}
dest=docs/bench/results
budgets=${BUDGETS:-1,2,4}
methods=${METHODS:-auto,pt:density,pt:equiangular,pt:mis,bdpt:density,bdpt:equiangular,bdpt:mis}
mkdir -p "$dest"

scenes=(scenes/*.gltf
        tests/data/single_near.gltf tests/data/single_spot.gltf tests/data/bdpt_quad_fogbox.gltf
        tests/data/bdpt_window_fog.gltf tests/data/bdpt_glass_sphere.gltf)
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .gltf)
  # Where light reaches the fog through glass only light tracing finds it: a bdpt reference.
  reference=pt:mis
  case "$name" in caustic | bdpt_glass_sphere) reference=bdpt:density ;; esac
  build/brume bench "$scene" --out "$work/$name" --reference-method "$reference" --budgets "$budgets" \
    --methods "$methods" | tee "$dest/$name.txt"
  cp "$work/$name/chart.png" "$dest/$name.png"
  cp "$work/$name/chart.svg" "$dest/$name.svg"
  cp "$work/$name/results.csv" "$dest/$name.csv"
done
