#!/usr/bin/env bash
# The area-light figures of docs/results.md ("Area lights close up"): every method at equal time
# on scenes/bench_panel.gltf in single scattering, each with and without the new strategies
# (METHOD:area = --emitter-sampling area); per-row relative variance at equal time (near the
# panel against far from it); and, given OLD=path/to/an/older/brume, the cost and efficiency of
# the default on scenes with small or far area lights against that build. About 15 minutes on
# 2 cores; run it on an otherwise idle machine.
#   bash docs/bench/area_lights.sh [WORKDIR]      (default build/bench-area)
#   BRUME=path/to/brume OLD=path/to/old/brume bash docs/bench/area_lights.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
work=${1:-build/bench-area}
brume=${BRUME:-build/brume}
dest=docs/bench/results
mkdir -p "$work" "$dest"

# Reference: pt:mis (solid angle) at 32768 spp; checked against pt:mis:area, pt:density and
# bdpt:mis images of the bench (image means within 0.1 %, docs/results.md).
[ -f "$work/panel_ref.exr" ] ||
  "$brume" render scenes/bench_panel.gltf -o "$work/panel_ref.exr" --res 48x32 --spp 32768 --integrator pt \
    --connect mis --max-depth 1 --seed 77
"$brume" bench scenes/bench_panel.gltf --out "$work/panel" --res 48x32 --max-depth 1 --budgets 2,8 \
  --reference "$work/panel_ref.exr" \
  --methods auto,auto:area,pt:mis,pt:mis:area,pt:density,pt:equiangular,bdpt:mis,bdpt:mis:area | tee "$dest/area_panel.txt"
cp "$work/panel/results.csv" "$dest/area_panel.csv"
cp "$work/panel/chart.png" "$dest/area_panel.png"
cp "$work/panel/chart.svg" "$dest/area_panel.svg"

# Rows: the four next to the panel against rows 8-31 (0.5 m and more below it), 8 seeds x 4 s.
/usr/bin/python3 docs/bench/panel_rows.py --brume "$brume" --scene scenes/bench_panel.gltf --time 4 --k 8 \
  "pt --connect mis" "pt --connect mis --emitter-sampling area" "auto" "auto --emitter-sampling area" |
  tee "$dest/area_panel_rows.txt"

# Small and far area lights, and none: the default and pt:mis against an older build.
if [ -n "${OLD:-}" ]; then
  for s in street area_hall; do
    [ -f "$work/${s}_ref.exr" ] ||
      "$brume" render "scenes/$s.gltf" -o "$work/${s}_ref.exr" --res 160x120 --spp 1024 --integrator pt --seed 99
  done
  for rep in 1 2 3; do
    for b in old new; do
      bin=$brume; [ $b = old ] && bin=$OLD
      for s in street area_hall; do
        "$bin" bench "scenes/$s.gltf" --out "$work/$s-$b-$rep" --res 160x120 --budgets 4 --reference "$work/${s}_ref.exr" \
          --methods pt:mis,auto --no-chart 2>/dev/null | grep -E "^$s " | awk -v b=$b -v r=$rep '{print b, r, $0}'
      done
    done
  done | tee "$dest/area_small_far.txt"
fi
