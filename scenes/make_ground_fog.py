#!/usr/bin/python3
"""Writes scenes/ground_fog.gltf and its density grid scenes/ground_fog.vdb: rolling ground fog
in a walled yard at night, lit by two lamps on posts.

Run: /usr/bin/python3 scenes/make_ground_fog.py   (needs Debian's python3-numpy and
python3-openvdb). The voxel values are deterministic (a fixed seed); the .vdb header carries
a random UUID.

The fog is the scene's ambient medium, a density grid in world space (docs/scene-format.md,
"density grids"): density = fbm(x, y, z) * exp(-y / 0.7), where fbm is four octaves of
trilinear value noise in [0.05, 1.8]; voxels 0.15 m over 24 m x 3.6 m x 24 m, zero above it.
Coefficients per unit density: scattering 0.45 /m, absorption 0.02 /m, g = 0.3.
"""

import math
import os
import sys

import numpy as np
import pyopenvdb as vdb

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True
sys.path.insert(0, HERE)
import gltfgen as g  # noqa: E402

VOXEL = 0.15
LO = (-80, 0, -100)   # voxel index bounds (inclusive): x in [-12, 12], y in [0, 3.6], z in [-15, 9]
HI = (80, 24, 60)
HEIGHT_SCALE = 0.7


def value_noise(x, y, z, freq, rng):
    """Trilinear value noise of a random lattice with spacing 1/freq (periodic, 64 cells)."""
    n = 64
    lattice = rng.random((n, n, n))
    fx, fy, fz = x * freq, y * freq, z * freq
    ix, iy, iz = np.floor(fx).astype(int), np.floor(fy).astype(int), np.floor(fz).astype(int)
    tx, ty, tz = fx - ix, fy - iy, fz - iz
    # smoothstep weights: no creases at the lattice planes
    tx, ty, tz = tx * tx * (3 - 2 * tx), ty * ty * (3 - 2 * ty), tz * tz * (3 - 2 * tz)
    out = 0.0
    for dx in (0, 1):
        for dy in (0, 1):
            for dz in (0, 1):
                w = (tx if dx else 1 - tx) * (ty if dy else 1 - ty) * (tz if dz else 1 - tz)
                out = out + w * lattice[(ix + dx) % n, (iy + dy) % n, (iz + dz) % n]
    return out


def fbm(x, y, z, octaves, freq, rng):
    """Fractal value noise in [0, 1]: octaves of value_noise from frequency freq, each of twice
    the frequency and half the weight of the one before."""
    out = np.zeros(np.shape(x))
    amp, total = 1.0, 0.0
    for octave in range(octaves):
        out += amp * value_noise(x, y, z, freq * 2 ** octave, rng)
        total += amp
        amp *= 0.5
    return out / total


def density_field():
    rng = np.random.default_rng(20261203)
    idx = np.indices(tuple(h - l + 1 for l, h in zip(LO, HI)))
    x, y, z = [(idx[a] + LO[a]) * VOXEL for a in range(3)]
    # stretched along x: banks of fog rolling across the yard
    noise = fbm(x * 0.7, y * 1.6, z, 4, 0.25, rng)
    shaped = 0.05 + 1.75 * np.clip((noise - 0.4) / 0.3, 0.0, 1.0)
    rho = shaped * np.exp(-y / HEIGHT_SCALE)
    rho[:, -1, :] = 0.0  # the top layer: the fog fades out inside the grid
    return rho.astype(np.float32)


def save_density(path, rho, lo, voxel):
    """Writes rho (indexed [x, y, z] from voxel index lo) as the float grid "density" of path,
    zeros inactive, voxels of the given size; returns the grid."""
    assert rho.min() >= 0 and np.isfinite(rho).all()
    grid = vdb.FloatGrid()
    grid.name = "density"
    grid.copyFromArray(rho, ijk=lo, tolerance=0)
    grid.transform = vdb.createLinearTransform(voxelSize=voxel)
    vdb.write(path, grids=[grid])
    return grid


def write_grid(path):
    rho = density_field()
    grid = save_density(path, rho, LO, VOXEL)
    print("  %s: %d active voxels, mean density %.3f, max %.3f" % (
        os.path.basename(path), grid.activeVoxelCount(), float(rho.mean()), float(rho.max())))


def add_box(b, name, material, lo, hi):
    size = g.sub(hi, lo)
    center = g.scale(g.add(lo, hi), 0.5)
    pos, nrm, uvs, idx = g.box(size, center)
    b.add_node(name, mesh=b.add_mesh(name, pos, idx, normals=nrm, material=material))


def write_scene(path, homogeneous_density=None):
    """homogeneous_density: instead of the grid, a homogeneous medium of that density filling
    the grid's box (an invisible boundary): the cost comparison of docs/results.md."""
    b = g.GltfBuilder("brume scenes/make_ground_fog.py")
    if homogeneous_density is None:
        fog = b.add_medium("ground_fog", scattering=0.45, absorption=0.02, anisotropy=0.3,
                           density={"uri": "ground_fog.vdb", "grid": "density", "scale": 1.0})
        b.set_ambient(fog)
    else:
        fog = b.add_medium("ground_fog", scattering=0.45 * homogeneous_density,
                           absorption=0.02 * homogeneous_density, anisotropy=0.3)
        lo = tuple(VOXEL * v for v in LO)
        hi = tuple(VOXEL * v for v in HI)
        size = g.sub(hi, lo)
        pos, _nrm, _uvs, idx = g.box(size, g.scale(g.add(lo, hi), 0.5))
        b.add_node("fog_box", mesh=b.add_mesh("fog_box", pos, idx, interior=fog))
    ground = b.add_material("ground", base_color=(0.16, 0.16, 0.15), roughness=1.0)
    stone = b.add_material("stone", base_color=(0.35, 0.33, 0.3), roughness=1.0)
    iron = b.add_material("iron", base_color=(0.05, 0.05, 0.055), roughness=0.8)
    wood = b.add_material("wood", base_color=(0.3, 0.2, 0.12), roughness=1.0)

    pos, nrm, uvs, idx = g.quad((0.0, 0.0, -3.0), (11.5, 0.0, 0.0), (0.0, 0.0, -11.5))
    assert g.triangle_normal(pos, idx, 0)[1] > 0.99, "the ground faces up"
    b.add_node("ground", mesh=b.add_mesh("ground", pos, idx, normals=nrm, material=ground))
    # yard walls: back, left, and a broken right wall with a gap
    add_box(b, "wall_back", stone, (-11.0, 0.0, -14.0), (11.0, 2.2, -13.4))
    add_box(b, "wall_left", stone, (-11.0, 0.0, -13.4), (-10.4, 1.6, 4.0))
    add_box(b, "wall_right_a", stone, (10.4, 0.0, -13.4), (11.0, 1.6, -6.0))
    add_box(b, "wall_right_b", stone, (10.4, 0.0, -3.5), (11.0, 1.6, 4.0))
    # a bench and a low crate for the fog to flow around
    add_box(b, "bench_seat", wood, (-3.2, 0.45, -5.2), (-1.0, 0.55, -4.8))
    add_box(b, "bench_leg_a", iron, (-3.1, 0.0, -5.15), (-3.0, 0.45, -4.85))
    add_box(b, "bench_leg_b", iron, (-1.2, 0.0, -5.15), (-1.1, 0.45, -4.85))
    add_box(b, "crate", wood, (2.5, 0.0, -8.6), (3.4, 0.9, -7.7))

    # two lamps on posts: warm sphere lights 3 m up
    lamps = [(-4.0, 3.0, -7.5), (3.2, 2.6, -3.5)]
    for k, (lx, ly, lz) in enumerate(lamps):
        add_box(b, "post_%d" % (k + 1), iron, (lx - 0.06, 0.0, lz - 0.06), (lx + 0.06, ly - 0.12, lz + 0.06))
        b.add_light("lamp_%d" % (k + 1), "point", (1.0, 0.78, 0.52), 60.0 if k == 0 else 35.0,
                    translation=(lx, ly, lz), radius=0.08)

    eye, target = (0.8, 2.3, 7.5), (-0.3, 0.5, -6.0)
    b.add_camera("camera", yfov=0.75, aspect_ratio=4.0 / 3.0, translation=eye, rotation=g.quat_look_at(eye, target))
    return b.write(path)


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--homogeneous":
        # python3 make_ground_fog.py --homogeneous OUT.gltf: the mean-density variant
        mean = float(density_field().mean())
        print("%s (homogeneous, density %.4f)" % (write_scene(sys.argv[2], mean), mean))
        return
    write_grid(os.path.join(HERE, "ground_fog.vdb"))
    print(os.path.relpath(write_scene(os.path.join(HERE, "ground_fog.gltf")), os.getcwd()))


if __name__ == "__main__":
    main()
