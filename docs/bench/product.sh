#!/usr/bin/env bash
# The product-sampling figures of docs/results.md ("Product sampling"): every --connect mode
# of pt and bdpt, plus auto, at equal time on bench_forward (g = 0.9, a point light in view),
# in single scattering and full transport; the g = 0 check on bench_fog_room (product is
# plain equi-angular there, to the bit); and the headlights showcase. Charts, tables and bench
# output go to docs/bench/results/product_*. About 25 minutes on 2 cores at the default
# budgets; run it on an otherwise idle machine.
#   bash docs/bench/product.sh [WORKDIR]      (default build/bench-product)
#   BUDGETS=4,16 bash docs/bench/product.sh
#   BRUME=path/to/brume bash docs/bench/product.sh   (default build/brume)
set -euo pipefail
cd "$(dirname "$0")/../.."
work=${1:-build/bench-product}
dest=docs/bench/results
budgets=${BUDGETS:-2,8}
brume=${BRUME:-build/brume}
all=pt:density,pt:equiangular,pt:product,pt:mis,bdpt:density,bdpt:equiangular,bdpt:product,bdpt:mis,auto
mkdir -p "$dest"

run() {  # NAME SCENE METHODS [bench options]
  local name=$1 scene=$2 methods=$3
  shift 3
  "$brume" bench "$scene" --out "$work/$name" --budgets "$budgets" --methods "$methods" "$@" | tee "$dest/$name.txt"
  cp "$work/$name/chart.png" "$dest/$name.png"
  cp "$work/$name/chart.svg" "$dest/$name.svg"
  cp "$work/$name/results.csv" "$dest/$name.csv"
}

run product_forward_single scenes/bench_forward.gltf "$all" --max-depth 1
run product_forward_full scenes/bench_forward.gltf "$all"
run product_g0_single scenes/bench_fog_room.gltf pt:density,pt:equiangular,pt:product,pt:mis --max-depth 1
# the path tracer's reference is firefly-ridden here (the rel. MSE of pt:mis at 1024 spp is ~0.08,
# the best methods' at 8 s ~0.2): the bidirectional one renders it
run product_headlights scenes/headlights.gltf "$all" --reference-method bdpt:mis
