#!/usr/bin/env bash
# The MPI figures of docs/results.md ("One image on many processes"): the time to sum the
# films of the ranks against the image size (an empty scene, so the passes cost nothing),
# and 1, 2 and 4 ranks on one machine against one process (this machine has 2 cores: 4 ranks
# are oversubscribed, so this measures overhead, not speed-up). Output to
# docs/bench/results/mpi.txt. A few minutes.
#   BRUME=path/to/brume bash docs/bench/mpi.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
brume=${BRUME:-build/brume}
out=docs/bench/results/mpi.txt
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpi="mpirun --oversubscribe"
{
  echo "reduction of the films to rank 0 (2 ranks, one machine), by image size:"
  for res in 480x270 960x540 1920x1080 3840x2160; do
    for rep in 1 2 3; do
      $mpi -np 2 "$brume" render tests/data/empty.gltf -o "$work/e.exr" --res $res --spp 2 --threads 1 |
        awk -v r=$res '/^ranks:/ {print r ": " $NF " " $(NF-1)}' | sed 's/ s / /'
    done
  done
  echo
  echo "bench_fog_room 320x240, 32 spp, pt --connect mis: seconds (wall), one process against N ranks"
  for rep in 1 2; do
    "$brume" render scenes/bench_fog_room.gltf -o "$work/a.exr" --res 320x240 --spp 32 --integrator pt --threads 2 |
      awk '{print "1 process, 2 threads: " $5 " s"; exit}'
    "$brume" render scenes/bench_fog_room.gltf -o "$work/a.exr" --res 320x240 --spp 32 --integrator pt --threads 1 |
      awk '{print "1 process, 1 thread: " $5 " s"; exit}'
    for n in 1 2 4; do
      $mpi -np $n "$brume" render scenes/bench_fog_room.gltf -o "$work/b.exr" --res 320x240 --spp 32 --integrator pt \
        --threads 1 | awk -v n=$n 'NR == 1 {t = $5} /^ranks:/ {print n " ranks x 1 thread: " t " s; " $0} n == 1 && NR == 1 {print n " rank x 1 thread: " t " s"}'
      cmp -s "$work/a.exr" "$work/b.exr" && echo "  (the same bits as one process)"
    done
  done
} | tee "$out"
