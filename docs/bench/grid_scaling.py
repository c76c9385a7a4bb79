#!/usr/bin/python3
"""Sparse density grids: memory against active voxels, and time against optical depth
(docs/results.md, "Production-sized grids"). Needs Debian's python3-openvdb, numpy and
matplotlib, and a built brume.

    /usr/bin/python3 docs/bench/grid_scaling.py BUILD/brume OUTDIR

Memory: a ball of radius R voxels (density falling from 1 at its centre to 0 at its edge) in a
small box (the ball alone) and in a 2048 x 1024 x 2048 box (an 8^3 block at the far corner);
brume's peak memory (a tiny render, so the figure is the scene's) against OpenVDB's own size of
the grid. Time: tests/data/single_gradient.gltf with its density scaled by s (the optical
depth across one voxel grows with s, up to the loader's limit of 1e4), pt at 16 spp, 64 x 48,
2 threads: seconds a sample. Writes grid_scaling.csv and grid_scaling.png to OUTDIR.
"""
import csv
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
import pyopenvdb as vdb

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def ball_grid(path, radius, far):
    n = 2 * radius
    z, y, x = np.mgrid[0:n, 0:n, 0:n].astype(np.float32)
    r = np.sqrt((x - radius) ** 2 + (y - radius) ** 2 + (z - radius) ** 2)
    a = np.where(r < radius, 1.0 - r / radius, 0.0).astype(np.float32)
    g = vdb.FloatGrid()
    g.copyFromArray(a, ijk=(0, 0, 0), tolerance=0)
    if far:
        g.copyFromArray(np.full((8, 8, 8), 0.5, np.float32), ijk=(2040, 1016, 2040), tolerance=0)
    g.name = "density"
    g.transform = vdb.createLinearTransform(voxelSize=0.01)
    vdb.write(path, grids=[g])
    return g.activeVoxelCount(), g.memUsage()


def peak_mib(brume, scene):
    out = subprocess.run(["/usr/bin/time", "-f", "PEAK %M", brume, "render", scene, "-o", scene + ".exr", "--spp", "1",
                          "--res", "8x6", "--threads", "2"], capture_output=True, text=True)
    m = re.search(r"PEAK (\d+)", out.stderr)
    if not m:
        raise RuntimeError(out.stderr)
    return int(m.group(1)) / 1024.0


def scene_with(path, uri, scale=None):
    with open(os.path.join(ROOT, "tests", "data", "single_gradient.gltf")) as f:
        doc = json.load(f)
    d = doc["extensions"]["BRUME_media"]["media"][0]["density"]
    d["uri"] = uri
    if scale is not None:
        d["scale"] = scale
    with open(path, "w") as f:
        json.dump(doc, f)


def main():
    brume, outdir = os.path.abspath(sys.argv[1]), sys.argv[2]
    os.makedirs(outdir, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for radius in (16, 32, 64, 100, 140):
            for far in (False, True):
                grid = os.path.join(tmp, "ball.vdb")
                active, vdb_bytes = ball_grid(grid, radius, far)
                scene = os.path.join(tmp, "ball.gltf")
                scene_with(scene, grid)
                peak = peak_mib(brume, scene)
                rows.append(["memory", radius, "2048x1024x2048" if far else "ball", active, vdb_bytes / 2**20, peak])
                print(rows[-1], flush=True)
        # the process without a grid: the same scene, homogeneous
        gradient = os.path.join(ROOT, "tests", "data", "gradient.vdb")
        for scale in (1, 10, 100, 1000, 10000, 89000):
            scene = os.path.join(tmp, "dense.gltf")
            scene_with(scene, gradient, scale)
            out = subprocess.run([brume, "render", scene, "-o", scene + ".exr", "--spp", "16", "--res", "64x48",
                                  "--threads", "2", "--integrator", "pt"], capture_output=True, text=True)
            m = re.search(r"(\d+) spp, ([\d.]+) s", out.stdout)
            if not m:
                raise RuntimeError(out.stdout + out.stderr)
            seconds = float(m.group(2)) / (64 * 48 * int(m.group(1)))
            tau = scale * 0.25 * 0.25 * 1.7875  # extinction x voxel x largest value (the loader's measure)
            rows.append(["time", scale, "single_gradient", tau, seconds * 1e6, ""])
            print(rows[-1], flush=True)
    with open(os.path.join(outdir, "grid_scaling.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["kind", "radius_or_scale", "box", "active_voxels_or_voxel_tau", "openvdb_mib_or_us_per_sample",
                    "brume_peak_mib"])
        w.writerows(rows)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    for box, style in (("ball", "o-"), ("2048x1024x2048", "s--")):
        r = [x for x in rows if x[0] == "memory" and x[2] == box]
        a.plot([x[3] for x in r], [x[5] for x in r], style, label="brume peak, box: " + box)
    r = [x for x in rows if x[0] == "memory" and x[2] == "ball"]
    a.plot([x[3] for x in r], [x[4] for x in r], "k:", label="OpenVDB's grid")
    a.set_xscale("log")
    a.set_yscale("log")
    a.set_xlabel("active voxels")
    a.set_ylabel("MiB")
    a.legend(fontsize=8)
    a.set_title("memory against active voxels")
    r = [x for x in rows if x[0] == "time"]
    b.plot([x[3] for x in r], [x[4] for x in r], "o-")
    b.set_xscale("log")
    b.set_xlabel("optical depth across one voxel")
    b.set_ylabel("µs a sample (pt, 2 threads)")
    b.set_title("time against optical depth")
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "grid_scaling.png"), dpi=90)


if __name__ == "__main__":
    main()
