#!/usr/bin/python3
"""Writes scenes/cumulus.gltf and its density grid scenes/cumulus.vdb: a sparse cumulus cloud
over a landscape in late-afternoon sun.

Run: /usr/bin/python3 scenes/make_cumulus.py   (needs Debian's python3-numpy and
python3-openvdb). The voxel values are deterministic (a fixed seed); the .vdb header carries
a random UUID.

The cloud: puffs (balls of random radii on a flat base) whose union, eroded by three octaves
of value noise, is the cloud's density; voxels 1 m, zero below the base at 60 m. Most of the
grid's bounding box is empty air: only voxels inside a puff are active. The cloud is the
interior medium of a box mesh around the grid (an invisible boundary), so the sun, a
directional light, reaches the landscape through clear air. Coefficients per unit density:
scattering 0.08 /m, absorption 0.001 /m, g = 0.6 (forward scattering; water droplets reach
0.85, whose sharper peak makes next-event estimation from the sun much noisier).
"""

import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True
sys.path.insert(0, HERE)
import gltfgen as g  # noqa: E402
from make_ground_fog import fbm, save_density  # noqa: E402

VOXEL = 1.0
LO = (-70, 58, -45)   # voxel index bounds (inclusive), metres
HI = (70, 130, 45)
BASE = 60.0


def puffs(rng):
    """(centre, radius) of the balls: a row of large ones on the base, smaller ones on top."""
    out = []
    for k in range(9):
        x = -48 + 12 * k + rng.uniform(-3, 3)
        r = rng.uniform(13, 19)
        out.append(((x, BASE + 0.6 * r, rng.uniform(-8, 8)), r))
    for k in range(7):
        x = rng.uniform(-35, 35)
        r = rng.uniform(9, 15)
        out.append(((x, BASE + 22 + rng.uniform(0, 18), rng.uniform(-10, 10)), r))
    return out


def density_field():
    rng = np.random.default_rng(20261205)
    idx = np.indices(tuple(h - l + 1 for l, h in zip(LO, HI)))
    x, y, z = [(idx[a] + LO[a]) * VOXEL for a in range(3)]
    inside = np.zeros(x.shape)
    for (cx, cy, cz), r in puffs(rng):
        d = np.sqrt((x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2) / r
        inside = np.maximum(inside, 1.0 - d)  # > 0 inside a puff, 1 at its centre
    noise = fbm(x, y, z, 3, 0.06, rng)
    rho = np.clip(inside * 4.0 - 0.35 * noise, 0.0, None)
    rho = np.minimum(rho, 1.0)
    rho[y < BASE] = 0.0  # a flat base
    return rho.astype(np.float32)


def write_grid(path):
    rho = density_field()
    grid = save_density(path, rho, LO, VOXEL)
    box = np.prod([h - l + 1 for l, h in zip(LO, HI)])
    print("  %s: %d active voxels of %d in the box (%.0f%%), max %.2f" % (
        os.path.basename(path), grid.activeVoxelCount(), box, 100.0 * grid.activeVoxelCount() / box, float(rho.max())))


def write_scene(path):
    b = g.GltfBuilder("brume scenes/make_cumulus.py")
    cloud = b.add_medium("cumulus", scattering=0.08, absorption=0.001, anisotropy=0.6,
                         density={"uri": "cumulus.vdb", "grid": "density", "scale": 1.0})
    lo = tuple(VOXEL * (v - 1) for v in LO)
    hi = tuple(VOXEL * (v + 1) for v in HI)
    pos, _nrm, _uvs, idx = g.box(g.sub(hi, lo), g.scale(g.add(lo, hi), 0.5))
    b.add_node("cloud_box", mesh=b.add_mesh("cloud_box", pos, idx, interior=cloud))

    grass = b.add_material("grass", base_color=(0.12, 0.16, 0.07), roughness=1.0)
    rock = b.add_material("rock", base_color=(0.3, 0.27, 0.24), roughness=1.0)
    pos, nrm, uvs, idx = g.quad((0.0, 0.0, -100.0), (400.0, 0.0, 0.0), (0.0, 0.0, -400.0))
    assert g.triangle_normal(pos, idx, 0)[1] > 0.99, "the ground faces up"
    b.add_node("ground", mesh=b.add_mesh("ground", pos, idx, normals=nrm, material=grass))
    # low hills on the horizon, and a rock in the foreground
    for k, (cx, cz, sx, sy) in enumerate([(-120, -260, 160, 22), (60, -300, 200, 30), (200, -220, 120, 18)]):
        pos, nrm, uvs, idx = g.box((sx, sy, 40.0), (cx, 0.5 * sy, cz))
        b.add_node("hill_%d" % (k + 1), mesh=b.add_mesh("hill_%d" % (k + 1), pos, idx, normals=nrm, material=grass))
    pos, nrm, uvs, idx = g.box((6.0, 3.0, 5.0), (14.0, 1.5, 30.0))
    b.add_node("rock", mesh=b.add_mesh("rock", pos, idx, normals=nrm, material=rock))

    # the sun, low in the west: warm, 3 W/m^2 on a surface facing it
    sun_dir = (0.75, -0.45, -0.35)
    b.add_light("sun", "directional", (1.0, 0.85, 0.68), 3.0, rotation=g.quat_look_dir(sun_dir))

    eye, target = (-30.0, 6.0, 150.0), (0.0, 55.0, 0.0)
    b.add_camera("camera", yfov=0.75, aspect_ratio=4.0 / 3.0, translation=eye, rotation=g.quat_look_at(eye, target))
    return b.write(path)


def main():
    write_grid(os.path.join(HERE, "cumulus.vdb"))
    print(os.path.relpath(write_scene(os.path.join(HERE, "cumulus.gltf")), os.getcwd()))


if __name__ == "__main__":
    main()
