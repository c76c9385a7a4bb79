#!/usr/bin/env bash
# The heterogeneous-media figures of docs/results.md ("Heterogeneous media"): every method at
# equal time on scenes/ground_fog.gltf (chart and table to docs/bench/results/vdb_ground_fog*),
# the cost per sample of the grid against a homogeneous medium of the same mean density in
# the same box (make_ground_fog.py --homogeneous), and the grid's memory against its active
# voxels. About 10 minutes on 2 cores; run it on an otherwise idle machine.
#   bash docs/bench/heterogeneous.sh [WORKDIR]      (default build/bench-vdb)
#   BRUME=path/to/brume BUDGETS=2,8 bash docs/bench/heterogeneous.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
work=${1:-build/bench-vdb}
brume=${BRUME:-build/brume}
budgets=${BUDGETS:-2,8}
dest=docs/bench/results
mkdir -p "$work" "$dest"

"$brume" bench scenes/ground_fog.gltf --out "$work/ground_fog" --budgets "$budgets" --reference-method bdpt:mis |
  tee "$dest/vdb_ground_fog.txt"
cp "$work/ground_fog/chart.png" "$dest/vdb_ground_fog.png"
cp "$work/ground_fog/chart.svg" "$dest/vdb_ground_fog.svg"
cp "$work/ground_fog/results.csv" "$dest/vdb_ground_fog.csv"

# Cost: seconds for 32 spp at 160x120, grid and homogeneous alternated, three times each.
/usr/bin/python3 scenes/make_ground_fog.py --homogeneous "$work/ground_fog_homogeneous.gltf"
cp scenes/ground_fog.vdb "$work/"
echo "cost per sample: seconds for 160x120 at 32 spp (grid, homogeneous)"
for method in "pt --connect density" "pt --connect mis" "bdpt --connect density" "bdpt --connect mis"; do
  for rep in 1 2 3; do
    g=$("$brume" render scenes/ground_fog.gltf -o "$work/cost.exr" --res 160x120 --spp 32 --integrator $method | awk 'NR == 1 {print $5}')
    h=$("$brume" render "$work/ground_fog_homogeneous.gltf" -o "$work/cost.exr" --res 160x120 --spp 32 --integrator $method | awk 'NR == 1 {print $5}')
    echo "$method: grid $g s, homogeneous $h s, ratio $(/usr/bin/python3 -c "print(round($g / $h, 2))")"
  done
done | tee "$dest/vdb_cost.txt"

# Memory: the file's active voxels against the dense copy brume keeps, and peak RSS.
/usr/bin/python3 - <<'PY' | tee "$dest/vdb_memory.txt"
import os
import pyopenvdb as vdb
path = "scenes/ground_fog.vdb"
g = vdb.read(path, "density")
lo, hi = g.evalActiveVoxelBoundingBox()
n = [h - l + 3 for l, h in zip(lo, hi)]
dense = n[0] * n[1] * n[2]
bricks = 1
for a in range(3):
    bricks *= max(1, (n[a] - 1 + 7) // 8)
print("%s: %d active voxels (%.2f MiB in OpenVDB, file %.2f MiB); dense copy %d voxels, %.2f MiB, "
      "+ %d bricks (%.3f MiB); dense/active %.2f"
      % (path, g.activeVoxelCount(), g.memUsage() / 2**20, os.path.getsize(path) / 2**20, dense, dense * 4 / 2**20,
         bricks, bricks * 8 / 2**20, dense / g.activeVoxelCount()))
PY
for f in scenes/ground_fog.gltf "$work/ground_fog_homogeneous.gltf"; do
  "$brume" render "$f" -o "$work/mem.exr" --res 160x120 --spp 4 | awk -v f="$f" 'NR == 1 {print f ": peak " $(NF-1) " " $NF}'
done | tee -a "$dest/vdb_memory.txt"
