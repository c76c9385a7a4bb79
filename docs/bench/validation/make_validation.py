#!/usr/bin/python3
"""Writes the validation scenes of docs/results.md ("Validation scenes") into a directory.

These scenes exist to judge MIS weights and the default's choices on scenes nothing was tuned
on: no constant, threshold or cost in brume was fitted on them, and their figures are reported
apart from the bundled scenes'. Their parameters (positions, coefficients, intensities) were
picked once, before any measurement, to differ from the bundled benchmark scenes.

  val_thin_lamp    thin grey fog, a point light in view behind a post (occluder)
  val_forward      g = 0.92 fog, a point light in view low over the ground
  val_side_panel   fog next to a vertical area light (a 0.8 m x 1.2 m panel on a wall)
  val_doorway      a lamp in the next room, seen through a doorway; multiple scattering
  val_glass_beam   a spot focused by a glass ball in fog (a volumetric caustic)
  val_fog_room     a point-lit room in denser fog, walls of albedo 0.7; multiple scattering

Run: /usr/bin/python3 docs/bench/validation/make_validation.py OUTDIR
"""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "..", "scenes"))
sys.dont_write_bytecode = True
import gltfgen as g  # noqa: E402
from make_scenes import Geometry, TexturedBuilder, box_between as box  # noqa: E402


def pnui(part):
    pos, nrm, uvs, idx = part
    return pos, idx, nrm, uvs


def ground(b, y=0.0, size=60.0, albedo=0.35, z=-30.0):
    m = b.add_material("ground", base_color=(albedo,) * 3, metallic=0.0, roughness=1.0)
    b.add_node("ground", mesh=b.add_mesh("ground", *pnui(g.quad((0.0, y, z), (0.0, 0.0, size), (size, 0.0, 0.0))),
                                         material=m))


def start(eye, target, yfov, aspect, fog, builder=g.GltfBuilder):
    """A builder with the camera at eye looking at target and ambient fog (σs, σa, g)."""
    b = builder("docs/bench/validation/make_validation.py")
    b.add_camera("camera", yfov=yfov, aspect_ratio=aspect, translation=eye, rotation=g.quat_look_at(eye, target))
    b.set_ambient(b.add_medium("fog", *fog))
    return b


def val_thin_lamp(path):
    b = start((0.4, 1.6, 1.0), (-1.0, 2.0, -9.0), 0.7, 4.0 / 3.0, (0.02, 0.002, 0.0))
    ground(b)
    post = b.add_material("post", base_color=(0.3, 0.3, 0.3), metallic=0.0, roughness=1.0)
    b.add_node("post", mesh=b.add_mesh("post", *pnui(box((-0.55, 0.0, -7.2), (-0.35, 3.2, -7.0))), material=post))
    b.add_light("lamp", "point", (1.0, 0.9, 0.7), 35.0, translation=(-1.2, 2.5, -9.0))
    return b.write(path)


def val_forward(path):
    b = start((0.0, 1.3, 0.0), (0.8, 1.2, -10.0), 0.75, 1.5, (0.04, 0.004, 0.92))
    ground(b, albedo=0.3)
    b.add_light("lamp", "point", (0.9, 0.95, 1.0), 15.0, translation=(1.5, 1.2, -10.0))
    return b.write(path)


def val_side_panel(path):
    b = start((0.0, 1.5, 0.0), (0.3, 1.4, -6.0), 0.8, 4.0 / 3.0, (0.08, 0.008, 0.2))
    ground(b, albedo=0.3)
    wall = b.add_material("wall", base_color=(0.4, 0.4, 0.4), metallic=0.0, roughness=1.0)
    b.add_node("wall", mesh=b.add_mesh("wall", *pnui(box((1.6, 0.0, -9.0), (1.8, 3.0, -2.0))), material=wall))
    panel = b.add_material("panel", base_color=(0.0, 0.0, 0.0), emissive=(1.0, 0.95, 0.85), emissive_strength=8.0)
    # On the wall's inner face (x = 1.6), facing -x, 0.8 m wide (z) and 1.2 m high.
    quad = g.quad((1.59, 1.6, -4.5), (0.0, 0.0, 0.4), (0.0, 0.6, 0.0))
    assert quad[1][0][0] < -0.999, "the panel faces -x"
    b.add_node("panel", mesh=b.add_mesh("panel", *pnui(quad), material=panel))
    return b.write(path)


def room_shell(geo, lo, hi):
    """Inward-facing quads of the box lo..hi."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    xc, yc, zc = 0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (z0 + z1)
    hx, hy, hz = 0.5 * (x1 - x0), 0.5 * (y1 - y0), 0.5 * (z1 - z0)
    geo.append(g.quad((xc, y0, zc), (0.0, 0.0, hz), (hx, 0.0, 0.0)))    # floor, +Y
    geo.append(g.quad((xc, y1, zc), (hx, 0.0, 0.0), (0.0, 0.0, hz)))    # ceiling, -Y
    geo.append(g.quad((xc, yc, z0), (hx, 0.0, 0.0), (0.0, hy, 0.0)))    # back, +Z
    geo.append(g.quad((xc, yc, z1), (0.0, hy, 0.0), (hx, 0.0, 0.0)))    # front, -Z
    geo.append(g.quad((x0, yc, zc), (0.0, hy, 0.0), (0.0, 0.0, hz)))    # left, +X
    geo.append(g.quad((x1, yc, zc), (0.0, 0.0, hz), (0.0, hy, 0.0)))    # right, -X


def val_doorway(path):
    b = start((1.2, 1.5, 2.5), (0.0, 1.3, -4.0), 0.8, 4.0 / 3.0, (0.06, 0.006, 0.3))
    wall = b.add_material("wall", base_color=(0.6, 0.6, 0.6), metallic=0.0, roughness=1.0)
    shell = Geometry()
    room_shell(shell, (-3.0, 0.0, -9.0), (3.0, 2.8, 3.5))
    # The dividing wall at z = -2 (0.15 thick), with a doorway 0.9 m wide, 2.1 m high at x = 0.
    for lo, hi in [((-3.0, 0.0, -2.15), (-0.45, 2.8, -2.0)), ((0.45, 0.0, -2.15), (3.0, 2.8, -2.0)),
                   ((-0.45, 2.1, -2.15), (0.45, 2.8, -2.0))]:
        shell.append(box(lo, hi))
    b.add_node("rooms", mesh=b.add_mesh("rooms", shell.positions, shell.indices, normals=shell.normals, uvs=shell.uvs,
                                        material=wall))
    # The lamp in the next room, off the line of sight through the door.
    b.add_light("lamp", "point", (1.0, 0.85, 0.65), 25.0, translation=(-1.8, 2.2, -5.5))
    return b.write(path)


def val_glass_beam(path):
    b = start((2.2, 1.2, 2.0), (0.0, 1.0, -1.0), 0.8, 4.0 / 3.0, (0.07, 0.005, 0.25), builder=TexturedBuilder)
    ground(b, albedo=0.4, size=20.0, z=-5.0)
    glass = b.add_glass("glass", 1.5)
    ball = g.uv_sphere(0.45, 48, 24, center=(0.0, 1.6, -1.0))
    b.add_node("ball", mesh=b.add_mesh("ball", *pnui(ball), material=glass))
    # A sphere lamp (a point light seen through glass alone would be out of the path tracer's
    # reach) over the ball, in a shade that limits it to a cone.
    b.add_light("lamp", "point", (1.0, 0.92, 0.8), 40.0, translation=(0.0, 3.6, -1.0), radius=0.2)
    shade = b.add_material("shade", base_color=(0.1, 0.1, 0.1), metallic=0.0, roughness=1.0)
    sg = Geometry()
    for lo, hi in [((-0.8, 3.3, -1.8), (-0.6, 4.0, -0.2)), ((0.6, 3.3, -1.8), (0.8, 4.0, -0.2)),
                   ((-0.8, 3.3, -1.8), (0.8, 4.0, -1.6)), ((-0.8, 3.3, -0.4), (0.8, 4.0, -0.2)),
                   ((-0.8, 4.0, -1.8), (0.8, 4.1, -0.2))]:
        sg.append(box(lo, hi))
    b.add_node("shade", mesh=b.add_mesh("shade", sg.positions, sg.indices, normals=sg.normals, uvs=sg.uvs, material=shade))
    return b.write(path)


def val_fog_room(path):
    b = start((-1.5, 1.2, 3.0), (0.5, 1.6, -5.0), 0.9, 1.5, (0.15, 0.01, 0.1))
    wall = b.add_material("wall", base_color=(0.7, 0.7, 0.7), metallic=0.0, roughness=1.0)
    shell = Geometry()
    room_shell(shell, (-3.5, 0.0, -7.0), (3.5, 3.2, 4.0))
    b.add_node("room", mesh=b.add_mesh("room", shell.positions, shell.indices, normals=shell.normals, uvs=shell.uvs,
                                       material=wall))
    b.add_light("lamp", "point", (1.0, 0.9, 0.8), 20.0, translation=(1.0, 2.6, -3.5))
    return b.write(path)


SCENES = [val_thin_lamp, val_forward, val_side_panel, val_doorway, val_glass_beam, val_fog_room]


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: make_validation.py OUTDIR")
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for make in SCENES:
        print(make(os.path.join(out, make.__name__ + ".gltf")))


if __name__ == "__main__":
    main()
