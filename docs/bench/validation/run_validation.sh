#!/usr/bin/env bash
# The validation figures of docs/results.md ("Validation scenes"): the scenes of
# make_validation.py (nothing in brume was fitted on them), every method at equal time, in full
# transport and single scattering. Tables and bench output go to docs/bench/results/val_*.
#   bash docs/bench/validation/run_validation.sh [WORKDIR]     (default build/bench-validation)
#   BUDGETS=4 METHODS=pt:mis,pt:product SCENES="val_forward" bash docs/bench/validation/run_validation.sh
#   BRUME=path/to/brume TAG=before bash docs/bench/validation/run_validation.sh   (another build, its own tables)
#   SEEDS="1 2 3" DEPTHS=full bash docs/bench/validation/run_validation.sh   (one run per seed, into
#       val_SCENE_DEPTH[_TAG]_sSEED.csv; tables.py --seeds takes each method's geometric mean)
# References: pt:mis at 1024 spp (bdpt:mis for the glass beam, where only light tracing
# finds the caustic), cached per scene in WORKDIR and shared between builds (pass the same WORKDIR).
set -euo pipefail
cd "$(dirname "$0")/../../.."
work=${1:-build/bench-validation}
dest=docs/bench/results
budgets=${BUDGETS:-4}
brume=${BRUME:-build/brume}
tag=${TAG:-}
methods=${METHODS:-pt:density,pt:equiangular,pt:product,pt:mis,bdpt:equiangular,bdpt:mis,auto}
scenes=${SCENES:-"val_thin_lamp val_forward val_side_panel val_doorway val_glass_beam val_fog_room"}
res=${RES:-160x120}
seeds=${SEEDS:-}
depths=${DEPTHS:-full single}
mkdir -p "$dest" "$work/scenes"
/usr/bin/python3 docs/bench/validation/make_validation.py "$work/scenes" > /dev/null

for scene in $scenes; do
  refmethod=pt:mis
  [ "$scene" = val_glass_beam ] && refmethod=bdpt:mis
  for depth in $depths; do
    depthopt=()
    [ "$depth" = single ] && depthopt=(--max-depth 1)
    name=${scene}_${depth}
    ref=$work/ref/$name
    if [ ! -f "$ref/reference.exr" ]; then  # the reference alone, once
      "$brume" bench "$work/scenes/$scene.gltf" --out "$ref" --budgets 0.1 --methods pt:density --res "$res" \
        --reference-method "$refmethod" --no-chart "${depthopt[@]}" > /dev/null
    fi
    for seed in ${seeds:-1}; do
      stem=${name}${tag:+_$tag}${seeds:+_s$seed}
      out=$work/$stem
      "$brume" bench "$work/scenes/$scene.gltf" --out "$out" --budgets "$budgets" --methods "$methods" --res "$res" \
        --reference "$ref/reference.exr" --no-chart --seed "$seed" "${depthopt[@]}" | tee "$dest/$stem.txt"
      cp "$out/results.csv" "$dest/$stem.csv"
    done
  done
done
