#!/usr/bin/python3
"""Writes the bundled scenes in scenes/ (currently street.gltf).

Run: /usr/bin/python3 scenes/make_scenes.py
The output is deterministic. See scenes/README.md.
"""

import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

sys.dont_write_bytecode = True  # no __pycache__ next to the scenes
import gltfgen as g  # noqa: E402


class Geometry:
    """Triangles accumulated in world space, written as one mesh."""

    def __init__(self):
        self.positions, self.normals, self.uvs, self.indices = [], [], [], []

    def append(self, part):
        pos, nrm, uvs, idx = part
        base = len(self.positions)
        self.positions += pos
        self.normals += nrm
        self.uvs += uvs
        self.indices += [base + i for i in idx]

    def triangles(self):
        return len(self.indices) // 3


def box_between(lo, hi):
    """Axis-aligned box from corner lo to corner hi."""
    size = tuple(hi[i] - lo[i] for i in range(3))
    assert all(s > 0 for s in size), (lo, hi)
    center = tuple(0.5 * (hi[i] + lo[i]) for i in range(3))
    return g.box(size, center)


def make_street(path):
    b = g.GltfBuilder("brume scenes/make_scenes.py")
    boxes = []      # world-space (lo, hi) of every solid, for the sanity checks below
    triangles = 0

    def add_geometry(name, geom, material):
        nonlocal triangles
        mesh = b.add_mesh(name, geom.positions, geom.indices, normals=geom.normals, uvs=geom.uvs,
                          material=material)
        b.add_node(name, mesh=mesh)
        triangles += geom.triangles()

    def solid(geom, lo, hi):
        geom.append(box_between(lo, hi))
        boxes.append((lo, hi))

    # ---- materials (metallicFactor 0 = Lambertian)
    m_ground = b.add_material("asphalt", base_color=(0.3, 0.3, 0.3))
    m_pavement = b.add_material("pavement", base_color=(0.3, 0.29, 0.28))
    m_facade = [b.add_material("facade_stone", base_color=(0.27, 0.24, 0.21)),
                b.add_material("facade_plaster", base_color=(0.33, 0.31, 0.29)),
                b.add_material("facade_brick", base_color=(0.26, 0.15, 0.11))]
    m_window = b.add_material("lit_window", base_color=(0.0, 0.0, 0.0),
                              emissive=(1.0, 0.72, 0.42), emissive_strength=1.5)
    m_iron = b.add_material("lamp_iron", base_color=(0.06, 0.06, 0.065))
    m_wood = b.add_material("crate_wood", base_color=(0.45, 0.3, 0.17))
    m_steel = b.add_material("polished_steel", base_color=(0.9, 0.88, 0.85), metallic=1.0, roughness=0.3)

    # ---- ground: 30 m (x) by 60 m (z), normal +Y
    ground = Geometry()
    ground.append(g.quad((0.0, 0.0, -22.0), (0.0, 0.0, 30.0), (15.0, 0.0, 0.0)))
    assert g.triangle_normal(ground.positions, ground.indices, 0)[1] > 0
    add_geometry("ground", ground, m_ground)

    # ---- pavements with kerbs: 0.15 m high, road x in [-4, 4] (bottoms sunk below the ground
    # plane so no faces are coplanar with it)
    pavement = Geometry()
    solid(pavement, (4.0, -0.05, -50.0), (6.5, 0.15, 8.0))
    solid(pavement, (-6.5, -0.05, -50.0), (-4.0, 0.15, 8.0))
    add_geometry("pavements", pavement, m_pavement)

    # ---- buildings: (x_lo, x_hi, z_far, z_near, height, material)
    blocks = [
        (6.5, 13.0, -4.0, 8.0, 9.0, 0), (6.5, 12.0, -17.0, -5.5, 14.0, 1),
        (6.5, 13.0, -28.0, -17.0, 7.5, 2), (6.5, 13.0, -50.0, -30.0, 11.0, 0),
        (-13.0, -6.5, -9.0, 8.0, 12.0, 2), (-12.0, -6.5, -24.0, -11.5, 8.0, 0),
        (-13.0, -6.5, -38.0, -24.0, 16.0, 1), (-13.0, -6.5, -50.0, -38.0, 10.0, 2),
        (-13.0, 13.0, -56.0, -50.0, 13.0, 1),  # closes the far end of the street
    ]
    facades = [Geometry() for _ in m_facade]
    for x0, x1, z0, z1, h, m in blocks:
        solid(facades[m], (x0, -0.05, z0), (x1, h, z1))
    for i, geom in enumerate(facades):
        add_geometry("buildings_%d" % i, geom, m_facade[i])

    # ---- a few lit windows, 2 cm in front of the street-facing facades (area lights)
    windows = Geometry()
    for x, y, z in ((-6.48, 4.2, -15.0), (-6.48, 4.2, -19.5), (-6.48, 7.4, -30.0),
                    (6.48, 3.8, -9.0), (6.48, 6.8, -36.0), (6.48, 3.8, -41.0)):
        side = 1.0 if x < 0 else -1.0                  # facing +X on the left, -X on the right
        u = (0.0, 0.0, -0.5 * side)                    # 1.0 m wide
        v = (0.0, 0.7, 0.0)                            # 1.4 m tall; u x v points to side * +X
        part = g.quad((x, y, z), u, v)
        assert g.dot(part[1][0], (side, 0.0, 0.0)) > 0.999
        windows.append(part)
    add_geometry("lit_windows", windows, m_window)

    # ---- street lamps: pole, arm, hood and hanger in iron; a warm sphere light under the hood
    lamp_color = (1.0, 0.72, 0.42)
    lamp_intensity = 40.0
    lamp_radius = 0.15
    iron = Geometry()
    lights = []
    for k, (px, pz) in enumerate(((4.6, -8.0), (-4.6, -20.0), (4.6, -32.0))):
        toward = -1.0 if px > 0 else 1.0               # the arm reaches over the road
        lx = px + toward * 1.0
        light_pos = (lx, 4.1, pz)
        solid(iron, (px - 0.07, 0.1, pz - 0.07), (px + 0.07, 4.55, pz + 0.07))            # pole
        solid(iron, (min(px, lx) - 0.05, 4.45, pz - 0.05), (max(px, lx) + 0.05, 4.55, pz + 0.05))  # arm
        solid(iron, (lx - 0.02, 4.36, pz - 0.02), (lx + 0.02, 4.45, pz + 0.02))           # hanger
        solid(iron, (lx - 0.22, 4.30, pz - 0.22), (lx + 0.22, 4.36, pz + 0.22))           # hood
        b.add_light("street_lamp_%d" % (k + 1), "point", lamp_color, lamp_intensity,
                    translation=light_pos, radius=lamp_radius)
        lights.append((light_pos, lamp_radius))

    # the spot at the end of the street: taller pole, cool white, pointing straight down
    spx, spz = -4.6, -38.0
    spot_pos = (-3.3, 6.0, spz)
    solid(iron, (spx - 0.08, 0.1, spz - 0.08), (spx + 0.08, 6.35, spz + 0.08))
    solid(iron, (spx - 0.05, 6.25, spz - 0.05), (spot_pos[0] + 0.2, 6.35, spz + 0.05))
    solid(iron, (spot_pos[0] - 0.2, 6.1, spz - 0.2), (spot_pos[0] + 0.2, 6.25, spz + 0.2))  # housing
    down = g.quat_axis_angle((1.0, 0.0, 0.0), -0.5 * math.pi)  # local -Z -> world -Y
    assert abs(g.quat_rotate(down, (0.0, 0.0, -1.0))[1] + 1.0) < 1e-12
    b.add_light("end_spot", "spot", (0.85, 0.92, 1.0), 300.0, translation=spot_pos, rotation=down,
                inner_cone=0.25, outer_cone=0.35)
    lights.append((spot_pos, 0.0))
    add_geometry("lamp_posts", iron, m_iron)

    # ---- crates on the right pavement near the first lamp (placed with node TRS; each sunk
    # 5 mm into what it stands on, so no faces are coplanar)
    crate_big = b.add_mesh("crate_large", *_pnui(g.box((0.8, 0.8, 0.8))), material=m_wood)
    crate_small = b.add_mesh("crate_small", *_pnui(g.box((0.55, 0.55, 0.55))), material=m_wood)
    b.add_node("crate_1", mesh=crate_big, translation=(5.5, 0.545, -10.0),
               rotation=g.quat_axis_angle((0, 1, 0), 0.15))
    b.add_node("crate_2", mesh=crate_small, translation=(5.45, 1.215, -10.05),
               rotation=g.quat_axis_angle((0, 1, 0), 0.6))
    b.add_node("crate_3", mesh=crate_big, translation=(5.6, 0.545, -11.0),
               rotation=g.quat_axis_angle((0, 1, 0), -0.1))
    boxes += [((5.0, 0.15, -10.5), (6.0, 0.95, -9.5)), ((5.05, 0.95, -10.45), (5.85, 1.5, -9.65)),
              ((5.1, 0.15, -11.5), (6.1, 0.95, -10.5))]
    triangles += 3 * 12

    # ---- a polished steel ball on a stone plinth on the left pavement, between lamps 1 and 2
    plinth = Geometry()
    solid(plinth, (-5.6, 0.1, -13.4), (-5.0, 0.9, -12.8))
    add_geometry("plinth", plinth, m_pavement)
    ball = b.add_mesh("steel_ball", *_pnui(g.uv_sphere(0.3, 24, 12)), material=m_steel)
    b.add_node("steel_ball", mesh=ball, translation=(-5.3, 1.19, -13.1))
    boxes.append(((-5.6, 0.9, -13.4), (-5.0, 1.5, -12.8)))
    triangles += 24 * 2 * 11

    # ---- media: ambient mist
    mist = b.add_medium("mist", scattering=0.05, absorption=0.005, anisotropy=0.3)
    b.set_ambient(mist)

    # ---- camera: eye height, in the mist, looking down the street and a little up
    eye = (0.6, 1.7, 6.0)
    target = (-0.3, 2.6, -40.0)
    yfov, aspect = 0.8, 4.0 / 3.0
    cam_rot = g.quat_look_at(eye, target)
    b.add_camera("camera", yfov=yfov, aspect_ratio=aspect, translation=eye, rotation=cam_rot)

    # ---- sanity checks
    def inside(p, lo, hi, margin=0.0):
        return all(lo[i] - margin < p[i] < hi[i] + margin for i in range(3))

    assert triangles < 5000, triangles
    assert not any(inside(eye, lo, hi, 0.1) for lo, hi in boxes), "camera inside a solid"
    for pos, r in lights:
        assert not any(inside(pos, lo, hi, r + 0.01) for lo, hi in boxes), "light %r touches a solid" % (pos,)
    # every light is in the picture (camera looks down local -Z, +Y up)
    fwd = g.quat_rotate(cam_rot, (0.0, 0.0, -1.0))
    up = g.quat_rotate(cam_rot, (0.0, 1.0, 0.0))
    right = g.quat_rotate(cam_rot, (1.0, 0.0, 0.0))
    tan_y = math.tan(0.5 * yfov)
    tan_x = tan_y * aspect
    for pos, _r in lights:
        d = g.sub(pos, eye)
        z = g.dot(d, fwd)
        sx, sy = g.dot(d, right) / (z * tan_x), g.dot(d, up) / (z * tan_y)
        assert z > 0 and abs(sx) < 0.95 and abs(sy) < 0.95, "light %r out of view (%g, %g)" % (pos, sx, sy)
        print("  light at (%.2f, %.2f, %.2f): film (%.0f, %.0f) of 640x480" %
              (pos[0], pos[1], pos[2], 320 * (1 + sx), 240 * (1 - sy)))
    print("  %d triangles" % triangles)
    return b.write(path)


def _pnui(part):
    """(positions, normals, uvs, indices) -> positional args of GltfBuilder.add_mesh."""
    pos, nrm, uvs, idx = part
    return pos, idx, nrm, uvs


def make_fog_bench(path, scattering, absorption, light_pos, intensity):
    """Benchmark scene for the light-connection strategies: a ground plane in homogeneous fog,
    one point light, the camera at eye height looking down the ground."""
    b = g.GltfBuilder("brume scenes/make_scenes.py")
    b.add_camera("camera", yfov=0.8, aspect_ratio=4.0 / 3.0, translation=(0.0, 1.5, 0.0))
    b.set_ambient(b.add_medium("fog", scattering, absorption, 0.3))
    ground = b.add_material("ground", base_color=(0.4, 0.4, 0.4), metallic=0.0, roughness=1.0)
    b.add_node("ground", mesh=b.add_mesh("ground", *_pnui(g.quad((0.0, 0.0, -40.0), (0.0, 0.0, 60.0),
                                                                     (60.0, 0.0, 0.0))), material=ground))
    b.add_light("light", "point", (1.0, 0.85, 0.6), intensity, translation=light_pos)
    return b.write(path)


def main():
    written = [
        make_street(os.path.join(HERE, "street.gltf")),
        # Thin fog, a point light close to the view rays: equi-angular sampling's home ground.
        make_fog_bench(os.path.join(HERE, "bench_thin_near.gltf"), 0.03, 0.003, (0.6, 1.8, -6.0), 20.0),
        # Dense fog, a distant light: free-flight sampling's home ground.
        make_fog_bench(os.path.join(HERE, "bench_dense_far.gltf"), 0.25, 0.01, (4.0, 4.0, -12.0), 60.0),
    ]
    for path in written:
        print(os.path.relpath(path, os.getcwd()))


if __name__ == "__main__":
    main()
