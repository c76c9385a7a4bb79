#!/usr/bin/python3
"""Writes scenes/campfire.gltf and its grids scenes/campfire.vdb: a campfire at night whose
flames light the smoke rising from it and the ground around it.

Run: /usr/bin/python3 scenes/make_campfire.py   (needs Debian's python3-numpy and
python3-openvdb). The voxel values are deterministic (fixed seeds); the .vdb header carries
a random UUID.

The fire is one medium, the interior of an invisible box (x, z in [-0.6, 0.6], y in
[-0.025, 2.45], its bottom under the ground) with two grids of voxels 2.5 cm (47 x 98 x 47)
in one file (docs/scene-format.md, "Emission"): "density", the smoke (a plume rising from the
flames' tips and widening as it climbs, thinning with height, eroded by value noise) plus a
little soot in the flames, and "flames", the emission (a teardrop about 0.45 m wide and 0.6 m
tall, torn into tongues by noise). Coefficients per unit density: scattering 4 /m, absorption
0.5 /m, g = 0.3; emission (6, 2.2, 0.5) x 40 per unit of "flames" (radiance per metre): the
flames' integral, 0.02 m^3, makes them about as bright as a point light of (4.8, 1.8, 0.4)
W/sr. The path tracer samples the flames as a volume light (docs/mis.md, "Emissive media");
the firelight the smoke scatters onto the haze and the ground is still reached only by the
paths' own directions, the grain that remains. Around it: a thin haze (scattering 0.02 /m,
absorption 0.002 /m, g = 0.3) in a box, vacuum beyond, so that a faint bluish moon (a
directional light, 0.5 W/m^2) reaches the ground; a ring of stones round the fire.
"""

import os
import sys

import numpy as np
import pyopenvdb as vdb

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True
sys.path.insert(0, HERE)
import gltfgen as g  # noqa: E402
from make_ground_fog import fbm, save_density  # noqa: E402

VOXEL = 0.025
LO = (-23, 0, -23)    # voxel index bounds (inclusive): x, z in [-0.575, 0.575], y in [0, 2.425]
HI = (23, 97, 23)
FLAME_TOP = 0.6       # height of the flames' tips, metres
FLAME_HALF_WIDTH = 0.22
EMISSION_RGB = (6.0, 2.2, 0.5)
EMISSION_SCALE = 40.0


def coordinates():
    """World coordinates (x, y, z) of the voxel centres, indexed [x, y, z]."""
    idx = np.indices(tuple(h - l + 1 for l, h in zip(LO, HI)))
    return [(idx[a] + LO[a]) * VOXEL for a in range(3)]


def edge_fade(x, y, z):
    """1 inside, falling to 0 over the last 5 cm of the grid: no hard faces at the box."""
    lo = [LO[a] * VOXEL for a in range(3)]
    hi = [HI[a] * VOXEL for a in range(3)]
    d = np.minimum.reduce([x - lo[0], hi[0] - x, hi[1] - y, z - lo[2], hi[2] - z])
    return np.clip(d / 0.05, 0.0, 1.0)


def flames_field(x, y, z):
    """Emission: a teardrop on the ground, widest 0.1-0.2 m up, to a point at FLAME_TOP; noise
    stretched upwards tears its edge and tips into tongues; hotter near the base."""
    rng = np.random.default_rng(20261206)
    h = np.clip(y / FLAME_TOP, 0.0, 1.0)
    half_width = FLAME_HALF_WIDTH * np.sqrt(np.clip(y / 0.1, 0.0, 1.0)) * (1.0 - h) ** 0.5
    r = np.sqrt(x * x + z * z)
    noise = fbm(x * 1.5, y * 0.4, z * 1.5, 3, 6.0, rng)  # blobs of about 10 cm, 40 cm tall
    shape = 1.0 - r / np.maximum(half_width, 1e-6) - 2.5 * (noise - 0.5)
    hot = np.clip(2.0 * shape, 0.0, 1.0) * (1.0 - 0.5 * h)
    hot[y >= FLAME_TOP] = 0.0
    return hot.astype(np.float32)


def density_field(x, y, z, flames):
    """Smoke: a plume from the flames' tips, radius 0.1 m there to 0.4 m at the top, leaning
    a little in +x, eroded by noise, thinning as it widens and dissolving in its top 0.6 m;
    plus soot of 0.15 in the flames."""
    rng = np.random.default_rng(20261207)
    rise = np.clip(y - 0.35, 0.0, None)
    radius = 0.1 + 0.14 * rise
    cx = 0.03 * rise ** 1.5
    d = np.sqrt((x - cx) ** 2 + z * z) / radius
    noise = fbm(x, y * 0.6, z, 4, 3.0, rng)
    body = np.clip(1.0 - d * d - 1.4 * (noise - 0.5), 0.0, 1.0)
    onset = np.clip((y - 0.35) / 0.3, 0.0, 1.0)  # the smoke starts in the flames' tips
    dissolve = np.clip((HI[1] * VOXEL - y) / 0.6, 0.0, 1.0)
    rho = 0.9 * body * onset * dissolve * (0.1 / radius) ** 0.8 + 0.15 * (flames > 0.02)
    return (rho * edge_fade(x, y, z)).astype(np.float32)


def write_grids(path):
    """Both grids into one file: save_density writes "density", then the file is rewritten
    with "flames" beside it."""
    x, y, z = coordinates()
    flames = flames_field(x, y, z)
    rho = density_field(x, y, z, flames)
    density = save_density(path, rho, LO, VOXEL)
    emission = vdb.FloatGrid()
    emission.name = "flames"
    emission.copyFromArray(flames, ijk=LO, tolerance=0)
    emission.transform = vdb.createLinearTransform(voxelSize=VOXEL)
    vdb.write(path, grids=[density, emission])
    for grid, values in ((density, rho), (emission, flames)):
        print("  %s %s: %d active voxels of %d, max %.2f" % (
            os.path.basename(path), grid.name, grid.activeVoxelCount(), values.size, float(values.max())))


def add_invisible_box(b, name, lo, hi, medium):
    """A closed box mesh without material: the boundary of `medium`."""
    pos, _nrm, _uvs, idx = g.box(g.sub(hi, lo), g.scale(g.add(lo, hi), 0.5))
    b.add_node(name, mesh=b.add_mesh(name, pos, idx, interior=medium))


def add_stones(b, material):
    """Nine low stones in a ring of radius 0.36 m round the fire."""
    rng = np.random.default_rng(20261208)
    for k in range(9):
        a = 2.0 * np.pi * (k + rng.uniform(-0.15, 0.15)) / 9
        size = (rng.uniform(0.1, 0.14), rng.uniform(0.06, 0.1), rng.uniform(0.08, 0.11))
        centre = (0.36 * np.cos(a), 0.5 * size[1], 0.36 * np.sin(a))
        pos, nrm, _uvs, idx = g.box(size, centre)
        rot = g.quat_axis_angle((0.0, 1.0, 0.0), -a)  # each stone faces the fire
        pos = [g.add(g.quat_rotate(rot, g.sub(p, centre)), centre) for p in pos]
        nrm = [g.quat_rotate(rot, n) for n in nrm]
        b.add_node("stone_%d" % (k + 1), mesh=b.add_mesh("stone_%d" % (k + 1), pos, idx, normals=nrm, material=material))


def write_scene(path):
    b = g.GltfBuilder("brume scenes/make_campfire.py")
    fire = b.add_medium("fire", scattering=4.0, absorption=0.5, anisotropy=0.3,
                        density={"uri": "campfire.vdb", "grid": "density", "scale": 1.0},
                        emission={"rgb": list(EMISSION_RGB), "uri": "campfire.vdb", "grid": "flames",
                                  "scale": EMISSION_SCALE})
    # the grid's bounds and one voxel beyond; the bottom under the ground
    add_invisible_box(b, "fire_box", tuple(VOXEL * (v - 1) for v in LO), tuple(VOXEL * (v + 1) for v in HI), fire)
    # bounded haze: a directional light's shadow rays leave it (in an ambient haze they would
    # cross infinite fog and bring nothing)
    haze = b.add_medium("haze", scattering=0.02, absorption=0.002, anisotropy=0.3)
    add_invisible_box(b, "haze_box", (-12.0, -0.5, -14.0), (12.0, 6.0, 8.0), haze)

    earth = b.add_material("earth", base_color=(0.22, 0.18, 0.14), roughness=1.0)
    stone = b.add_material("stone", base_color=(0.35, 0.33, 0.3), roughness=1.0)
    pos, nrm, _uvs, idx = g.quad((0.0, 0.0, -3.0), (10.0, 0.0, 0.0), (0.0, 0.0, -10.0))
    assert g.triangle_normal(pos, idx, 0)[1] > 0.99, "the ground faces up"
    b.add_node("ground", mesh=b.add_mesh("ground", pos, idx, normals=nrm, material=earth))
    add_stones(b, stone)

    # a faint cool moon, high in the back left
    moon_dir = (0.4, -0.7, 0.6)
    b.add_light("moon", "directional", (0.55, 0.65, 1.0), 0.5, rotation=g.quat_look_dir(moon_dir))

    eye, target = (0.0, 1.2, 4.5), (0.0, 0.8, 0.0)
    b.add_camera("camera", yfov=0.7, aspect_ratio=1.777, translation=eye, rotation=g.quat_look_at(eye, target))
    return b.write(path)


def main():
    write_grids(os.path.join(HERE, "campfire.vdb"))
    print(os.path.relpath(write_scene(os.path.join(HERE, "campfire.gltf")), os.getcwd()))


if __name__ == "__main__":
    main()
