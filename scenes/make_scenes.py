#!/usr/bin/python3
"""Writes the bundled scenes in scenes/ (street, the fog benchmarks and the lit-fog showcase
scenes: panel_room, next_room, god_rays, area_hall, caustic, smoke_box, lighthouse, dusk_haze,
headlights).

Run: /usr/bin/python3 scenes/make_scenes.py
The output is deterministic. See scenes/README.md.
"""

import base64
import math
import os
import struct
import sys
import zlib

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


def make_fog_bench(path, scattering, absorption, light_pos, intensity, anisotropy=0.3):
    """Benchmark scene for the light-connection strategies: a ground plane in homogeneous fog
    (Henyey-Greenstein g = anisotropy), one point light, the camera at eye height looking down
    the ground."""
    b = g.GltfBuilder("brume scenes/make_scenes.py")
    eye, yfov, aspect = (0.0, 1.5, 0.0), 0.8, 4.0 / 3.0
    b.add_camera("camera", yfov=yfov, aspect_ratio=aspect, translation=eye)
    assert light_pos[1] > 0.5, "the light is above the ground"
    View(eye, (0.0, 0.0, 0.0, 1.0), yfov, aspect).assert_in_view("light", light_pos)
    b.set_ambient(b.add_medium("fog", scattering, absorption, anisotropy))
    ground = b.add_material("ground", base_color=(0.4, 0.4, 0.4), metallic=0.0, roughness=1.0)
    b.add_node("ground", mesh=b.add_mesh("ground", *_pnui(g.quad((0.0, 0.0, -40.0), (0.0, 0.0, 60.0),
                                                                     (60.0, 0.0, 0.0))), material=ground))
    b.add_light("light", "point", (1.0, 0.85, 0.6), intensity, translation=light_pos)
    return b.write(path)


# =============================================================================================
# Lit-fog showcase scenes: god_rays, area_hall, caustic, smoke_box, lighthouse.
# Shared helpers first: a builder that also writes PNG textures, extra geometry (tapered
# cylinders, discs, tori, rocks), and the geometric checks each scene asserts.

class TexturedBuilder(g.GltfBuilder):
    """GltfBuilder plus embedded PNG textures (data URIs) and glass materials."""

    def __init__(self, generator="brume scenes/make_scenes.py"):
        super().__init__(generator)
        self.images = []

    def add_png_texture(self, name, png_bytes):
        uri = "data:image/png;base64," + base64.b64encode(png_bytes).decode("ascii")
        self.images.append({"name": name, "mimeType": "image/png", "uri": uri})
        return len(self.images) - 1  # one texture per image, same index

    def add_glass(self, name, ior=1.5):
        """Smooth glass: KHR_materials_transmission 1 + KHR_materials_ior."""
        m = self.add_material(name, base_color=(1.0, 1.0, 1.0), metallic=0.0, roughness=0.0)
        self.materials[m]["extensions"] = {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                           "KHR_materials_ior": {"ior": float(ior)}}
        self.extensions_used.update(("KHR_materials_transmission", "KHR_materials_ior"))
        return m

    def add_textured_emitter(self, name, texture, emissive, strength):
        """Black base colour; radiance = texture (linear) x emissive x strength."""
        m = self.add_material(name, base_color=(0.02, 0.02, 0.02), emissive=emissive,
                              emissive_strength=strength)
        self.materials[m]["emissiveTexture"] = {"index": texture}
        return m

    def document(self):
        doc = super().document()
        if self.images:
            doc["images"] = self.images
            doc["samplers"] = [{"magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497}]
            doc["textures"] = [{"sampler": 0, "source": i} for i in range(len(self.images))]
        return doc


def png_rgb(width, height, pixel):
    """An 8-bit RGB PNG (standard library only); pixel(x, y) -> (r, g, b) in 0..255, y = 0 at
    the top row."""
    raw = bytearray()
    for y in range(height):
        raw.append(0)  # filter: none
        for x in range(width):
            raw.extend(bytes(pixel(x, y)))

    def chunk(tag, data):
        crc = zlib.crc32(tag + data) & 0xFFFFFFFF
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", crc)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b""))


def _hash01(*ints):
    """Deterministic pseudo-random number in [0, 1) from integers."""
    h = 2166136261
    for i in ints:
        for byte in struct.pack("<i", int(i)):
            h = ((h ^ byte) * 16777619) & 0xFFFFFFFF
    h ^= h >> 13
    h = (h * 0x5BD1E995) & 0xFFFFFFFF
    h ^= h >> 15
    return h / 4294967296.0


def transformed(part, rotation=None, translation=(0.0, 0.0, 0.0)):
    """A (positions, normals, uvs, indices) part rotated by a glTF quaternion, then moved."""
    pos, nrm, uvs, idx = part
    if rotation is not None:
        pos = [g.quat_rotate(rotation, p) for p in pos]
        nrm = [g.quat_rotate(rotation, n) for n in nrm]
    return [g.add(p, translation) for p in pos], list(nrm), list(uvs), list(idx)


def cylinder(base, r_bottom, r_top, height, segments, cap_bottom=True, cap_top=True):
    """Tapered cylinder along +Y from `base`, front faces outward, smooth side normals, flat
    caps with their own vertices (at the same positions as the side's rims, so with both caps
    the surface is closed for ray tracing, though not by shared indices)."""
    pos, nrm, uvs, idx = [], [], [], []
    slope = (r_bottom - r_top) / height

    def ring_point(r, y, j):
        phi = 2.0 * math.pi * j / segments
        return g.add(base, (r * math.cos(phi), y, -r * math.sin(phi)))  # counter-clockwise from +Y

    for j in range(segments):
        phi = 2.0 * math.pi * j / segments
        n = g.normalize((math.cos(phi), slope, -math.sin(phi)))
        for r, y, v in ((r_bottom, 0.0, 1.0), (r_top, height, 0.0)):
            pos.append(ring_point(r, y, j))
            nrm.append(n)
            uvs.append((j / segments, v))
    for j in range(segments):
        a, b = 2 * j, 2 * ((j + 1) % segments)
        idx += [a, b, b + 1, a, b + 1, a + 1]
    for cap, r, y, up in ((cap_bottom, r_bottom, 0.0, -1.0), (cap_top, r_top, height, 1.0)):
        if not cap or r <= 0:
            continue
        centre = len(pos)
        pos.append(g.add(base, (0.0, y, 0.0)))
        for j in range(segments):
            pos.append(ring_point(r, y, j))
        nrm += [(0.0, up, 0.0)] * (segments + 1)
        uvs += [(0.5, 0.5)] * (segments + 1)
        for j in range(segments):
            a, b = centre + 1 + j, centre + 1 + (j + 1) % segments
            idx += [centre, a, b] if up > 0 else [centre, b, a]
    return pos, nrm, uvs, idx


def disc(center, u_axis, v_axis, radius, segments):
    """Triangle fan: a flat disc, front face normal = u_axis x v_axis."""
    u, v = g.normalize(u_axis), g.normalize(v_axis)
    n = g.normalize(g.cross(u, v))
    pos, uvs = [center], [(0.5, 0.5)]
    for j in range(segments):
        phi = 2.0 * math.pi * j / segments
        c, s = math.cos(phi), math.sin(phi)
        pos.append(g.add(center, g.add(g.scale(u, radius * c), g.scale(v, radius * s))))
        uvs.append((0.5 + 0.5 * c, 0.5 - 0.5 * s))
    idx = []
    for j in range(segments):
        idx += [0, 1 + j, 1 + (j + 1) % segments]
    return pos, [n] * len(pos), uvs, idx


def torus(major, minor, seg_major, seg_minor):
    """Torus about the origin, ring in the XY plane (axis +Z), front faces outward, closed."""
    pos, nrm, uvs, idx = [], [], [], []
    for i in range(seg_major):
        a = 2.0 * math.pi * i / seg_major
        ca, sa = math.cos(a), math.sin(a)
        for j in range(seg_minor):
            b = 2.0 * math.pi * j / seg_minor
            cb, sb = math.cos(b), math.sin(b)
            n = (cb * ca, cb * sa, sb)
            pos.append(((major + minor * cb) * ca, (major + minor * cb) * sa, minor * sb))
            nrm.append(n)
            uvs.append((i / seg_major, j / seg_minor))
    for i in range(seg_major):
        for j in range(seg_minor):
            a = i * seg_minor + j
            b = ((i + 1) % seg_major) * seg_minor + j
            c = ((i + 1) % seg_major) * seg_minor + (j + 1) % seg_minor
            d = i * seg_minor + (j + 1) % seg_minor
            idx += [a, b, c, a, c, d]
    return pos, nrm, uvs, idx


def rock(center, size, seed, segments=10, rings=6):
    """A lumpy closed boulder: a UV sphere scaled by size = (sx, sy, sz), each vertex pushed in
    or out by a deterministic pseudo-random factor in [0.75, 1.2], and raised by 0.7 sy so that
    its bottom is sunk into the ground at center[1]. Returns (positions, indices, (lo, hi)) for
    a flat-shaded mesh."""
    pos, _n, _uv, idx = g.uv_sphere(1.0, segments, rings)
    out = []
    for k, p in enumerate(pos):
        f = 0.75 + 0.45 * _hash01(seed, k)
        out.append((center[0] + p[0] * size[0] * f, center[1] + (p[1] * f + 0.7) * size[1],
                    center[2] + p[2] * size[2] * f))
    lo = tuple(min(p[i] for p in out) for i in range(3))
    hi = tuple(max(p[i] for p in out) for i in range(3))
    return out, idx, (lo, hi)


class Checks:
    """World-space bounding boxes of the solids, for asserting that the camera and the lights
    are in free space and that the openings light should pass are clear."""

    def __init__(self):
        self.boxes = []  # (lo, hi, name)

    def solid(self, lo, hi, name=""):
        assert all(lo[i] < hi[i] for i in range(3)), (lo, hi, name)
        self.boxes.append((tuple(lo), tuple(hi), name))

    def blocker(self, p, margin=0.0):
        for lo, hi, name in self.boxes:
            if all(lo[i] - margin < p[i] < hi[i] + margin for i in range(3)):
                return name or repr((lo, hi))
        return None

    def assert_free(self, what, p, margin=0.05):
        name = self.blocker(p, margin)
        assert name is None, "%s at %r is inside (or within %g m of) solid %s" % (what, p, margin, name)

    def segment_blocker(self, p0, p1):
        """A solid the open segment p0-p1 passes through, or None (slab test)."""
        d = g.sub(p1, p0)
        for lo, hi, name in self.boxes:
            t0, t1 = 1e-9, 1.0 - 1e-9
            for i in range(3):
                if abs(d[i]) < 1e-15:
                    if not lo[i] < p0[i] < hi[i]:
                        break
                    continue
                a, b = (lo[i] - p0[i]) / d[i], (hi[i] - p0[i]) / d[i]
                t0, t1 = max(t0, min(a, b)), min(t1, max(a, b))
                if t0 >= t1:
                    break
            else:
                return name or repr((lo, hi))
        return None

    def assert_clear(self, what, p0, p1):
        name = self.segment_blocker(p0, p1)
        assert name is None, "%s: the segment %r -> %r is blocked by %s" % (what, p0, p1, name)

    def assert_blocked(self, what, p0, p1):
        assert self.segment_blocker(p0, p1) is not None, "%s: %r -> %r is not blocked" % (what, p0, p1)


class View:
    """The camera's frame, to place points on the 640x480 film."""

    def __init__(self, eye, rotation, yfov, aspect):
        self.eye = eye
        self.fwd = g.quat_rotate(rotation, (0.0, 0.0, -1.0))
        self.up = g.quat_rotate(rotation, (0.0, 1.0, 0.0))
        self.right = g.quat_rotate(rotation, (1.0, 0.0, 0.0))
        self.tan_y = math.tan(0.5 * yfov)
        self.tan_x = self.tan_y * aspect

    def film(self, p):
        d = g.sub(p, self.eye)
        z = g.dot(d, self.fwd)
        if z <= 0:
            return None
        return g.dot(d, self.right) / (z * self.tan_x), g.dot(d, self.up) / (z * self.tan_y)

    def assert_in_view(self, what, p, limit=0.95):
        f = self.film(p)
        assert f is not None and abs(f[0]) < limit and abs(f[1]) < limit, \
            "%s %r out of view (%r)" % (what, p, f)
        print("  %s at (%.2f, %.2f, %.2f): film (%.0f, %.0f) of 640x480" %
              (what, p[0], p[1], p[2], 320 * (1 + f[0]), 240 * (1 - f[1])))


class Parts:
    """Meshes of one scene with the triangle count and the checks."""

    def __init__(self, b):
        self.b = b
        self.checks = Checks()
        self.triangles = 0
        self.geoms = {}  # material -> Geometry of boxes in world space

    def box(self, material, lo, hi, name=""):
        """An opaque axis-aligned box, merged with the other boxes of its material."""
        self.geoms.setdefault(material, Geometry()).append(box_between(lo, hi))
        self.checks.solid(lo, hi, name)

    def mesh(self, name, part, material, interior=None, smooth=True, solid=True):
        pos, nrm, uvs, idx = part
        mesh = self.b.add_mesh(name, pos, idx, normals=nrm if smooth else None, uvs=uvs,
                               material=material, interior=interior)
        self.b.add_node(name, mesh=mesh)
        self.triangles += len(idx) // 3
        if solid:
            lo = tuple(min(p[i] for p in pos) for i in range(3))
            hi = tuple(max(p[i] for p in pos) for i in range(3))
            if all(lo[i] < hi[i] for i in range(3)):
                self.checks.solid(lo, hi, name)
        return mesh

    def fog_box(self, name, lo, hi, medium):
        """Invisible closed boundary of the box [lo, hi] enclosing `medium` (no material)."""
        pos, _n, _uv, idx = box_between(lo, hi)
        size = g.sub(hi, lo)
        assert abs(g.signed_volume(pos, idx) - size[0] * size[1] * size[2]) < 1e-9
        self.b.add_node(name, mesh=self.b.add_mesh(name, pos, idx, interior=medium))
        self.triangles += 12

    def flush(self, names):
        """Write the merged boxes, one mesh per material (names: material -> mesh name)."""
        for material, geom in self.geoms.items():
            mesh = self.b.add_mesh(names[material], geom.positions, geom.indices, normals=geom.normals,
                                   uvs=geom.uvs, material=material)
            self.b.add_node(names[material], mesh=mesh)
            self.triangles += geom.triangles()
        self.geoms = {}


def aim(direction):
    """Rotation taking local -Z onto `direction`, checked."""
    d = g.normalize(direction)
    q = g.quat_look_dir(d)
    r = g.quat_rotate(q, (0.0, 0.0, -1.0))
    assert all(abs(r[i] - d[i]) < 1e-9 for i in range(3)), (r, d)
    return q


# ---------------------------------------------------------------------------------------------
# god_rays.gltf

def make_god_rays(path):
    """A dusty room lit by the sun through two mullioned windows in its back wall, and by a
    cold spot shining in through the right-hand window from outside. Dust inside only (a
    bounded medium just inside the walls): outside is vacuum, so the directional sun reaches
    the windows unattenuated."""
    b = TexturedBuilder()
    parts = Parts(b)
    m_plaster = b.add_material("plaster", base_color=(0.62, 0.58, 0.52))
    m_floor = b.add_material("floorboards", base_color=(0.36, 0.25, 0.16))
    m_wood = b.add_material("dark_wood", base_color=(0.22, 0.14, 0.08))
    m_frame = b.add_material("window_frame", base_color=(0.12, 0.11, 0.1))

    # Room interior x in [-4, 4], y in [0, 4], z in [-8, 0]; walls 0.25 m thick.
    X, H, Z, T = 4.0, 4.0, -8.0, 0.25
    parts.box(m_floor, (-X - T, -T, Z - T), (X + T, 0.0, T), "floor")
    parts.box(m_plaster, (-X - T, H, Z - T), (X + T, H + T, T), "ceiling")
    parts.box(m_plaster, (-X - T, 0.0, Z - T), (-X, H, T), "left wall")
    parts.box(m_plaster, (X, 0.0, Z - T), (X + T, H, T), "right wall")
    parts.box(m_plaster, (-X, 0.0, 0.0), (X, H, T), "front wall")
    # Back wall (z in [Z - T, Z]) around two windows, y in [wy0, wy1]
    wy0, wy1 = 1.5, 3.4
    windows = [(-2.7, -1.1), (0.7, 2.3)]  # x ranges
    parts.box(m_plaster, (-X, 0.0, Z - T), (X, wy0, Z), "back wall below")
    parts.box(m_plaster, (-X, wy1, Z - T), (X, H, Z), "back wall above")
    edges = [-X] + [x for w in windows for x in w] + [X]
    for k in range(0, len(edges), 2):
        parts.box(m_plaster, (edges[k], wy0, Z - T), (edges[k + 1], wy1, Z), "back wall pier %d" % k)
    # Mullion crosses, in the middle of the wall's thickness
    for x0, x1 in windows:
        xm, ym = 0.5 * (x0 + x1), 0.5 * (wy0 + wy1)
        parts.box(m_frame, (xm - 0.04, wy0, Z - 0.16), (xm + 0.04, wy1, Z - 0.09), "mullion")
        parts.box(m_frame, (x0, ym - 0.04, Z - 0.16), (xm - 0.04, ym + 0.04, Z - 0.09), "transom")
        parts.box(m_frame, (xm + 0.04, ym - 0.04, Z - 0.16), (x1, ym + 0.04, Z - 0.09), "transom")
    # Furniture: a table in the sunlight, a bench, a tall cupboard against the left wall
    tx, tz = -0.6, -4.4
    parts.box(m_wood, (tx - 0.9, 0.74, tz - 0.5), (tx + 0.9, 0.8, tz + 0.5), "table top")
    for sx in (-1, 1):
        for sz in (-1, 1):
            lx, lz = tx + sx * 0.8, tz + sz * 0.4
            parts.box(m_wood, (lx - 0.04, 0.0, lz - 0.04), (lx + 0.04, 0.74, lz + 0.04), "table leg")
    parts.box(m_wood, (tx - 0.8, 0.0, tz + 0.75), (tx + 0.8, 0.45, tz + 1.05), "bench")
    parts.box(m_wood, (-X, 0.0, -3.2), (-X + 0.6, 2.4, -1.6), "cupboard")
    parts.flush({m_plaster: "walls", m_floor: "floor", m_wood: "furniture", m_frame: "window_frames"})

    # Dust: inside the room only
    dust = b.add_medium("dust", scattering=0.08, absorption=0.004, anisotropy=0.6)
    e = 0.005
    parts.fog_box("dusty_air", (-X + e, e, Z + e), (X - e, H - e, -e), dust)

    centres = [(0.5 * (x0 + x1), 0.5 * (wy0 + wy1), Z - 0.5 * T) for x0, x1 in windows]
    # The sky: a large, faint emissive wall far behind the back wall, seen through the windows
    # but low enough not to shade the windows from the high sun
    m_sky = b.add_material("sky", base_color=(0.0, 0.0, 0.0), emissive=(0.55, 0.7, 1.0),
                           emissive_strength=0.6)
    # (only as large as the windows need: the sun's share of the light samples grows with the
    # scene's size)
    sky_z, sky_x, sky_y = Z - 7.0, (-9.5, 3.5), (-0.5, 5.4)
    sky = g.quad((0.5 * (sky_x[0] + sky_x[1]), 0.5 * (sky_y[0] + sky_y[1]), sky_z),
                 (0.5 * (sky_x[1] - sky_x[0]), 0.0, 0.0), (0.0, 0.5 * (sky_y[1] - sky_y[0]), 0.0))
    assert sky[1][0][2] > 0.999, "the sky faces the room"
    parts.mesh("sky", sky, m_sky, solid=False)
    parts.checks.solid((sky_x[0], sky_y[0], sky_z - 0.01), (sky_x[1], sky_y[1], sky_z), "sky")
    eye = (2.9, 1.5, -0.7)  # the camera (below)
    for c in centres:  # the camera sees the sky through the windows' upper and lower panes
        for qy in (-0.45, 0.45):
            pane = g.add(c, (-0.4, qy, 0.0))
            ray = g.sub(pane, eye)
            q = g.add(eye, g.scale(ray, (sky_z + 0.005 - eye[2]) / ray[2]))
            assert sky_x[0] < q[0] < sky_x[1] and sky_y[0] < q[1] < sky_y[1], "sky missed at %r" % (q,)
            parts.checks.assert_clear("sky seen through the window", eye, q)

    # The sun: direction of travel into the room through the back wall, from high up
    sun_dir = g.normalize((0.32, -0.62, 1.0))
    sun_rot = aim(sun_dir)
    b.add_light("sun", "directional", (1.0, 0.9, 0.75), 9.0,
                translation=g.sub(centres[0], g.scale(sun_dir, 6.0)), rotation=sun_rot)
    for k, c in enumerate(centres):
        # the sun reaches the room through each window's four panes (not through the mullions)
        for qx in (-0.4, 0.4):
            for qy in (-0.45, 0.45):
                p = g.add(c, (qx, qy, 0.0))
                parts.checks.assert_clear("sun through window %d" % k, g.sub(p, g.scale(sun_dir, 40.0)),
                                          g.add(p, g.scale(sun_dir, 0.3)))
        # and the pane's sunlight lands on the floor inside the room
        t = c[1] / -sun_dir[1]
        land = g.add(c, g.scale(sun_dir, t))
        assert -X < land[0] < X and Z < land[2] < 0, "sun patch %r outside the room" % (land,)
        print("  sun patch of window %d on the floor at (%.2f, %.2f)" % (k, land[0], land[2]))
    parts.checks.assert_blocked("sun blocked by the back wall", (0.0, 0.8, Z - 3.0), (0.0, 0.8, Z + 1.0))

    # The spot: outside, behind and above the right window, shining in through it; its cone is
    # wider than the window (which shapes the beam), which also gives it a fair share of the
    # light samples next to the sun (brume picks lights by power)
    win = centres[1]
    spot_dir = g.normalize((-0.3, -0.8, 1.0))
    spot_pos = g.sub(win, g.scale(spot_dir, 3.0))
    b.add_light("street_spot", "spot", (0.5, 0.68, 1.0), 250.0, translation=spot_pos, rotation=aim(spot_dir),
                inner_cone=0.5, outer_cone=0.7)
    for qx in (-0.8, 0.8):  # the whole window is inside the inner cone
        for qy in (-0.95, 0.95):
            corner = g.sub(g.add(win, (qx, qy, 0.0)), spot_pos)
            assert math.acos(g.dot(g.normalize(corner), spot_dir)) < 0.5
    assert spot_pos[2] < Z - T, "the spot must be outside the room"
    parts.checks.assert_free("spot", spot_pos)
    parts.checks.assert_clear("spot through the right window", spot_pos, g.add(win, (0.35, 0.4, 0.0)))
    parts.checks.assert_clear("spot through the right window", spot_pos, g.add(win, (0.35, -0.4, 0.0)))

    # Camera: front right corner, eye height, looking at the windows
    target = (-0.8, 2.0, -8.0)
    yfov, aspect = 0.95, 4.0 / 3.0
    rot = g.quat_look_at(eye, target)
    b.add_camera("camera", yfov=yfov, aspect_ratio=aspect, translation=eye, rotation=rot)
    parts.checks.assert_free("camera", eye, 0.1)
    view = View(eye, rot, yfov, aspect)
    for k, c in enumerate(centres):
        view.assert_in_view("window %d" % k, c)
    view.assert_in_view("table", (tx, 0.8, tz))
    assert parts.triangles < 50000, parts.triangles
    print("  %d triangles" % parts.triangles)
    return b.write(path)


# ---------------------------------------------------------------------------------------------
# area_hall.gltf

def stained_glass_png(width=96, height=144):
    """A pointed-arch window: a rose of eight coloured sectors over a lattice of diamond
    quarries, black lead lines; black outside the arch (no emission there)."""
    palette = [(40, 70, 200), (190, 25, 35), (235, 170, 30), (30, 150, 70), (120, 50, 170),
               (60, 150, 220)]
    lead = (10, 9, 8)
    margin = 5.0
    x0, x1 = margin, width - margin
    spring = 0.36 * height                    # where the arch starts
    r_arch = 0.8 * (x1 - x0)                  # pointed (two-centred) arch
    rose_c, rose_r = (0.5 * width, 0.33 * height), 0.3 * width

    def pixel(x, y):
        px, py = x + 0.5, y + 0.5
        if not x0 <= px <= x1 or py > height - margin:
            return (0, 0, 0)
        if py < spring:
            # inside both circles centred at the springing line, r_arch from the opposite side
            if (math.hypot(px - (x1 - r_arch), py - spring) > r_arch
                    or math.hypot(px - (x0 + r_arch), py - spring) > r_arch):
                return (0, 0, 0)
        # lead around the edge of the glass
        if px - x0 < 1.5 or x1 - px < 1.5 or height - margin - py < 1.5:
            return lead
        dx, dy = px - rose_c[0], py - rose_c[1]
        rr = math.hypot(dx, dy)
        if rr < rose_r:
            if abs(rr - rose_r) < 1.5 or abs(rr - 0.35 * rose_r) < 1.2:
                return lead
            if rr < 0.35 * rose_r:
                return (245, 210, 90)
            a = (math.atan2(dy, dx) / (2.0 * math.pi) + 1.0 / 16.0) % 1.0 * 8.0
            if min(a % 1.0, 1.0 - a % 1.0) * rr * 2.0 * math.pi / 8.0 < 0.9:
                return lead
            return palette[1] if int(a) % 2 == 0 else palette[0]
        # diamond quarries
        cell = 12.0
        u, v = (px + py) / cell, (px - py) / cell
        fu, fv = u - math.floor(u), v - math.floor(v)
        if min(fu, 1 - fu) * cell < 0.8 or min(fv, 1 - fv) * cell < 0.8:
            return lead
        k = int(_hash01(math.floor(u), math.floor(v)) * len(palette))
        return palette[k]

    return png_rgb(width, height, pixel)


def make_area_hall(path):
    """A stone hall in thin fog, lit only by area lights: a rectangular ceiling panel, a
    round ceiling light (triangle fan), a stained-glass window (emissive texture) in the end
    wall and a neon ring (emissive torus) on a plinth."""
    b = TexturedBuilder()
    parts = Parts(b)
    m_stone = b.add_material("stone", base_color=(0.5, 0.48, 0.45))
    m_floor = b.add_material("floor_tiles", base_color=(0.32, 0.3, 0.28), metallic=0.3, roughness=0.35)
    m_dark = b.add_material("plinth", base_color=(0.08, 0.08, 0.09))

    # Interior x in [-5, 5], y in [0, 5], z in [-16, 0]; walls 0.3 m thick
    X, H, Z, T = 5.0, 5.0, -16.0, 0.3
    parts.box(m_floor, (-X - T, -T, Z - T), (X + T, 0.0, T), "floor")
    parts.box(m_stone, (-X - T, H, Z - T), (X + T, H + T, T), "ceiling")
    parts.box(m_stone, (-X - T, 0.0, Z - T), (-X, H, T), "left wall")
    parts.box(m_stone, (X, 0.0, Z - T), (X + T, H, T), "right wall")
    parts.box(m_stone, (-X, 0.0, Z - T), (X, H, Z), "end wall")
    parts.box(m_stone, (-X, 0.0, 0.0), (X, H, T), "entrance wall")
    # Pillars along both sides
    for z in (-3.5, -7.5, -11.5):
        for x in (-3.6, 3.6):
            parts.box(m_stone, (x - 0.35, 0.0, z - 0.35), (x + 0.35, H, z + 0.35), "pillar")
    parts.box(m_dark, (-2.0, 0.0, -10.5), (-1.0, 0.5, -9.5), "plinth")
    parts.flush({m_stone: "walls_and_pillars", m_floor: "floor", m_dark: "plinth"})
    lights = []

    # 1. Rectangle: a ceiling panel over the left aisle, facing down, warm white
    m_panel = b.add_material("panel_light", base_color=(0.0, 0.0, 0.0), emissive=(1.0, 0.85, 0.65),
                             emissive_strength=12.0)
    rect = g.quad((-2.0, H - 0.02, -7.0), (0.0, 0.0, -1.2), (0.35, 0.0, 0.0))
    assert rect[1][0][1] < -0.999, "the panel must face down"
    parts.mesh("rect_light", rect, m_panel, solid=False)
    lights.append(("rectangle light", (-2.0, H - 0.05, -7.0)))

    # 2. Disc: a round ceiling light over the right aisle, facing down, cool white
    m_disc = b.add_material("disc_light", base_color=(0.0, 0.0, 0.0), emissive=(0.7, 0.85, 1.0),
                            emissive_strength=14.0)
    dsk = disc((2.2, H - 0.02, -11.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.55, 32)
    assert dsk[1][0][1] < -0.999, "the disc must face down"
    parts.mesh("disc_light", dsk, m_disc, solid=False)
    lights.append(("disc light", (2.2, H - 0.05, -11.0)))

    # 3. Textured panel: a stained-glass window on the end wall, facing the hall (+Z)
    tex = b.add_png_texture("stained_glass", stained_glass_png())
    m_glass = b.add_textured_emitter("stained_glass", tex, emissive=(1.0, 0.95, 0.85), strength=5.0)
    sg_c = (0.0, 2.7, Z + 0.02)
    sg = g.quad(sg_c, (1.35, 0.0, 0.0), (0.0, 2.0, 0.0))
    assert sg[1][0][2] > 0.999 and abs(sg[2][3][1]) < 1e-12, "window faces +Z, texture top at the top"
    parts.mesh("stained_glass", sg, m_glass, solid=False)
    lights.append(("stained glass", g.add(sg_c, (0.0, 0.0, 0.05))))

    # 4. Emissive mesh: a magenta neon ring standing on the plinth, facing the camera
    m_neon = b.add_material("neon", base_color=(0.05, 0.05, 0.05), emissive=(1.0, 0.15, 0.6),
                            emissive_strength=10.0)
    ring_c = (-1.5, 1.55, -10.0)
    ring = transformed(torus(0.95, 0.045, 64, 8), translation=ring_c)
    g.check_closed(ring[3])
    assert g.signed_volume(ring[0], ring[3]) > 0, "the ring's faces point inward"
    assert ring_c[1] - 0.95 - 0.045 > 0.5, "the ring stands clear of the plinth"
    parts.mesh("neon_ring", ring, m_neon, solid=False)  # a hoop: its bounding box is not solid
    lights.append(("neon ring", (ring_c[0], ring_c[1] + 0.95, ring_c[2] + 0.1)))

    b.set_ambient(b.add_medium("haze", scattering=0.035, absorption=0.003, anisotropy=0.25))

    eye = (1.1, 1.7, -0.8)
    target = (-0.3, 3.0, -16.0)
    yfov, aspect = 0.95, 4.0 / 3.0
    rot = g.quat_look_at(eye, target)
    b.add_camera("camera", yfov=yfov, aspect_ratio=aspect, translation=eye, rotation=rot)
    parts.checks.assert_free("camera", eye, 0.1)
    view = View(eye, rot, yfov, aspect)
    for what, p in lights:
        view.assert_in_view(what, p)
        parts.checks.assert_clear("line of sight to the " + what, eye, p)
    assert parts.triangles < 50000, parts.triangles
    print("  %d triangles" % parts.triangles)
    return b.write(path)


# ---------------------------------------------------------------------------------------------
# caustic.gltf

def make_caustic(path):
    """A glass ball in fog under a shaded lamp: the ball focuses the lamp's cone into a bright
    volumetric caustic (a thin cone converging below it) inside the ball's shadow.

    The lamp is a small sphere light inside an opaque shade that opens downwards (a spot
    light made of geometry): a true spot light is a point, which the path tracer can never
    reach through glass, so it would leave the caustic black."""
    b = TexturedBuilder()
    parts = Parts(b)
    m_floor = b.add_material("floor", base_color=(0.55, 0.55, 0.55))
    m_shade = b.add_material("shade", base_color=(0.05, 0.05, 0.05), metallic=0.0)
    m_glass = b.add_glass("glass", 1.5)

    floor = g.quad((0.0, 0.0, -4.0), (0.0, 0.0, 7.0), (7.0, 0.0, 0.0))
    assert floor[1][0][1] > 0.999
    parts.mesh("floor", floor, m_floor, solid=False)

    ball_c, ball_r = (0.0, 1.55, -4.0), 0.55
    ball = g.uv_sphere(ball_r, 64, 32, center=ball_c)
    g.check_closed(ball[3])
    parts.mesh("glass_ball", ball, m_glass)

    lamp = (0.0, 3.95, -4.0)
    lamp_r = 0.3
    # the shade: an open-bottomed cone (radius 0.4 at the top, 0.5 at the rim) with a cap
    rim_y, top_y, rim_r, top_r = 3.2, 4.35, 0.5, 0.4
    shade = cylinder((lamp[0], rim_y, lamp[2]), rim_r, top_r, top_y - rim_y, 48,
                     cap_bottom=False, cap_top=True)
    parts.mesh("lamp_shade", shade, m_shade, solid=False)
    b.add_light("lamp", "point", (1.0, 0.93, 0.8), 60.0, translation=lamp, radius=lamp_r)
    # the lamp hangs inside the shade, clear of it; its cone covers the ball
    half_angle = math.atan2(rim_r, lamp[1] - rim_y)
    ball_angle = math.asin(ball_r / (lamp[1] - ball_c[1]))
    assert ball_angle < half_angle, (ball_angle, half_angle)
    assert lamp[1] + lamp_r < top_y and rim_y < lamp[1] - lamp_r
    shade_r_at_lamp = rim_r + (top_r - rim_r) * (lamp[1] - rim_y) / (top_y - rim_y)
    assert lamp_r < shade_r_at_lamp - 0.05, "the lamp touches its shade"
    print("  lamp cone half-angle %.1f deg, the ball fills %.1f deg" %
          (math.degrees(half_angle), math.degrees(ball_angle)))
    parts.checks.solid((lamp[0] - rim_r, rim_y, lamp[2] - rim_r), (lamp[0] + rim_r, top_y, lamp[2] + rim_r),
                       "shade")
    # a thin cord to the (unseen) ceiling
    parts.mesh("cord", cylinder((lamp[0], top_y, lamp[2]), 0.008, 0.008, 3.0, 8), m_shade, solid=False)

    # paraxial focus of a ball lens: f = n R / (2 (n - 1)) from the centre; image of the lamp
    f = 1.5 * ball_r / (2.0 * 0.5)
    s = lamp[1] - ball_c[1]
    focus_y = ball_c[1] - 1.0 / (1.0 / f - 1.0 / s)
    assert 0.1 < focus_y < ball_c[1] - ball_r, focus_y
    print("  paraxial focus %.2f m above the floor" % focus_y)

    b.set_ambient(b.add_medium("fog", scattering=0.09, absorption=0.008, anisotropy=0.35))

    eye = (1.3, 1.45, 1.2)
    target = (0.0, 1.95, -4.0)
    yfov, aspect = 0.9, 4.0 / 3.0
    rot = g.quat_look_at(eye, target)
    b.add_camera("camera", yfov=yfov, aspect_ratio=aspect, translation=eye, rotation=rot)
    parts.checks.assert_free("camera", eye, 0.1)
    view = View(eye, rot, yfov, aspect)
    view.assert_in_view("lamp shade", (lamp[0], top_y, lamp[2]))
    view.assert_in_view("glass ball", ball_c)
    view.assert_in_view("focus", (0.0, focus_y, ball_c[2]))
    assert parts.triangles < 50000, parts.triangles
    print("  %d triangles" % parts.triangles)
    return b.write(path)


# ---------------------------------------------------------------------------------------------
# smoke_box.gltf

def make_smoke_box(path):
    """A closed wooden box full of dense smoke with a lamp inside; light escapes through a
    square hole in its front wall into thin haze (bounded, vacuum beyond) over the ground. A
    faint moon lights the outside."""
    b = TexturedBuilder()
    parts = Parts(b)
    m_ground = b.add_material("ground", base_color=(0.3, 0.3, 0.28))
    m_box = b.add_material("box_wood", base_color=(0.5, 0.36, 0.22))

    ground = g.quad((0.0, 0.0, -6.0), (0.0, 0.0, 14.0), (14.0, 0.0, 0.0))
    assert ground[1][0][1] > 0.999
    parts.mesh("ground", ground, m_ground, solid=False)

    # Box interior x in [-1, 1], y in [0.1, 2.1], z in [zc - 1, zc + 1]; walls 0.1 m thick
    zc, T = -5.0, 0.1
    lo_i, hi_i = (-1.0, 0.1, zc - 1.0), (1.0, 2.1, zc + 1.0)
    hole = ((0.2, 0.5), (0.8, 1.1))  # x range, y range of the opening in the front wall (0.3 m square)
    parts.box(m_box, (lo_i[0] - T, -0.02, lo_i[2] - T), (hi_i[0] + T, lo_i[1], hi_i[2] + T), "bottom")
    parts.box(m_box, (lo_i[0] - T, hi_i[1], lo_i[2] - T), (hi_i[0] + T, hi_i[1] + T, hi_i[2] + T), "lid")
    parts.box(m_box, (lo_i[0] - T, lo_i[1], lo_i[2] - T), (lo_i[0], hi_i[1], hi_i[2] + T), "left")
    parts.box(m_box, (hi_i[0], lo_i[1], lo_i[2] - T), (hi_i[0] + T, hi_i[1], hi_i[2] + T), "right")
    parts.box(m_box, (lo_i[0], lo_i[1], lo_i[2] - T), (hi_i[0], hi_i[1], lo_i[2]), "back")
    fz0, fz1 = hi_i[2], hi_i[2] + T
    (hx0, hx1), (hy0, hy1) = hole
    parts.box(m_box, (lo_i[0], lo_i[1], fz0), (hi_i[0], hy0, fz1), "front below")
    parts.box(m_box, (lo_i[0], hy1, fz0), (hi_i[0], hi_i[1], fz1), "front above")
    parts.box(m_box, (lo_i[0], hy0, fz0), (hx0, hy1, fz1), "front left")
    parts.box(m_box, (hx1, hy0, fz0), (hi_i[0], hy1, fz1), "front right")
    parts.flush({m_box: "box"})

    smoke = b.add_medium("smoke", scattering=2.0, absorption=0.2, anisotropy=0.2)
    haze = b.add_medium("haze", scattering=0.06, absorption=0.004, anisotropy=0.4)
    e = 0.002
    parts.fog_box("smoke", g.add(lo_i, (e, e, e)), g.sub(hi_i, (e, e, e)), smoke)
    parts.fog_box("haze", (-16.0, -0.5, -22.0), (16.0, 8.0, 10.0), haze)

    lamp = (0.3, 1.2, hi_i[2] - 0.35)  # 0.35 m behind the hole and above it: a beam leaves it
    b.add_light("lamp", "point", (1.0, 0.78, 0.5), 250.0, translation=lamp, radius=0.08)
    parts.checks.assert_free("lamp", lamp, 0.1)
    assert all(lo_i[i] + 0.2 < lamp[i] < hi_i[i] - 0.2 for i in range(3)), "the lamp is inside the box"
    hole_c = (0.5 * (hx0 + hx1), 0.5 * (hy0 + hy1), fz1)
    parts.checks.assert_clear("lamp through the hole", lamp, g.add(hole_c, (0.0, 0.0, 0.05)))
    parts.checks.assert_blocked("the box is closed elsewhere", lamp, (-2.0, 1.0, zc + 2.0))
    parts.checks.assert_blocked("the box is closed elsewhere", lamp, (0.0, 3.0, zc))

    moon_dir = g.normalize((0.5, -0.6, -0.6))
    b.add_light("moon", "directional", (0.55, 0.65, 1.0), 0.6, translation=(0.0, 8.0, 0.0),
                rotation=aim(moon_dir))

    eye = (2.6, 1.55, 0.2)
    target = (-0.3, 0.9, -5.0)
    yfov, aspect = 0.8, 4.0 / 3.0
    rot = g.quat_look_at(eye, target)
    b.add_camera("camera", yfov=yfov, aspect_ratio=aspect, translation=eye, rotation=rot)
    parts.checks.assert_free("camera", eye, 0.1)
    view = View(eye, rot, yfov, aspect)
    view.assert_in_view("hole", hole_c)
    parts.checks.assert_clear("camera sees into the hole", eye, g.add(hole_c, (0.0, 0.0, -0.2)))
    assert parts.triangles < 50000, parts.triangles
    print("  %d triangles" % parts.triangles)
    return b.write(path)


# ---------------------------------------------------------------------------------------------
# lighthouse.gltf

def make_lighthouse(path):
    """Night on a rocky shore in sea fog: a lighthouse on a headland sweeps a narrow beam that
    passes just to the right of the viewer."""
    b = TexturedBuilder()
    parts = Parts(b)
    m_ground = b.add_material("turf", base_color=(0.12, 0.13, 0.1))
    m_rock = b.add_material("rock", base_color=(0.28, 0.27, 0.25))
    m_white = b.add_material("whitewash", base_color=(0.75, 0.74, 0.72))
    m_red = b.add_material("red_paint", base_color=(0.5, 0.08, 0.06))
    m_iron = b.add_material("iron", base_color=(0.05, 0.05, 0.05))
    m_lantern = b.add_material("lantern", base_color=(0.1, 0.1, 0.1), emissive=(1.0, 0.85, 0.55),
                               emissive_strength=12.0)

    ground = g.quad((0.0, 0.0, -40.0), (0.0, 0.0, 80.0), (80.0, 0.0, 0.0))
    assert ground[1][0][1] > 0.999
    parts.mesh("ground", ground, m_ground, solid=False)

    # The lighthouse on a mound of rock
    base = (-9.0, 0.0, -23.0)
    parts.mesh("tower", cylinder(base, 1.7, 1.15, 13.0, 32), m_white)
    parts.mesh("tower_band", cylinder(g.add(base, (0.0, 8.0, 0.0)), 1.38, 1.33, 1.6, 32), m_red)
    parts.mesh("gallery", cylinder(g.add(base, (0.0, 13.0, 0.0)), 1.7, 1.7, 0.25, 32), m_iron)
    lantern_r = 0.6
    parts.mesh("lantern_room", cylinder(g.add(base, (0.0, 13.25, 0.0)), lantern_r, lantern_r, 1.5, 24),
               m_lantern)
    parts.mesh("roof", cylinder(g.add(base, (0.0, 14.75, 0.0)), 1.1, 0.05, 1.0, 24), m_red)
    lantern = g.add(base, (0.0, 14.0, 0.0))
    # the keeper's cottage at the foot of the tower, two lit windows facing the viewer
    cottage_lo, cottage_hi = (-7.0, 0.0, -22.0), (-2.5, 2.8, -19.0)
    parts.mesh("cottage", box_between(cottage_lo, cottage_hi), m_white)
    parts.mesh("cottage_roof", box_between(g.add(cottage_lo, (-0.2, 2.8, -0.2)),
                                           g.add(cottage_hi, (0.2, 0.5, 0.2))), m_red)
    m_window = b.add_material("cottage_window", base_color=(0.0, 0.0, 0.0), emissive=(1.0, 0.7, 0.38),
                              emissive_strength=4.0)
    cottage_windows = Geometry()
    for wx in (cottage_lo[0] + 1.2, cottage_hi[0] - 1.3):
        part = g.quad((wx, 1.5, cottage_hi[2] + 0.02), (0.35, 0.0, 0.0), (0.0, 0.45, 0.0))
        assert part[1][0][2] > 0.999
        cottage_windows.append(part)
    parts.mesh("cottage_windows", (cottage_windows.positions, cottage_windows.normals, cottage_windows.uvs,
                                   cottage_windows.indices), m_window, solid=False)
    # a lamp over the cottage's side door, lighting the foot of the tower and the rocks
    door_lamp = (cottage_lo[0] - 0.25, 2.3, cottage_hi[2] - 0.8)
    b.add_light("door_lamp", "point", (1.0, 0.75, 0.45), 6.0, translation=door_lamp, radius=0.06)
    parts.checks.assert_free("door lamp", door_lamp, 0.1)

    rocks = Geometry()
    rock_specs = [  # (x, z, sx, sy, sz)
        (-9.0, -23.0, 5.5, 1.4, 4.5), (-1.0, -17.5, 1.6, 0.7, 1.4), (-13.5, -20.5, 3.5, 1.1, 3.0),
        (-14.0, -15.0, 2.0, 0.8, 1.8), (3.5, -9.0, 1.6, 0.9, 1.3), (5.5, -12.5, 2.2, 1.2, 1.8),
        (-2.8, -6.5, 1.2, 0.6, 1.0), (-4.5, -10.5, 1.8, 0.8, 1.4), (1.6, -5.0, 0.6, 0.35, 0.5),
        (8.0, -18.0, 3.0, 1.5, 2.4), (-8.0, -16.0, 2.4, 1.0, 2.0), (12.0, -30.0, 4.0, 1.8, 3.0),
    ]
    for k, (x, z, sx, sy, sz) in enumerate(rock_specs):
        pos, idx, (lo, hi) = rock((x, 0.0, z), (sx, sy, sz), seed=k + 1)
        base_i = len(rocks.positions)
        rocks.positions += pos
        rocks.indices += [base_i + i for i in idx]
        if k > 0:  # the mound under the tower is not a box
            parts.checks.solid(lo, hi, "rock %d" % k)
    g.check_closed(rocks.indices)
    b.add_node("rocks", mesh=b.add_mesh("rocks", rocks.positions, rocks.indices, material=m_rock))
    parts.triangles += rocks.triangles()

    # The beam: a narrow spot from the lantern, aimed just right of and above the viewer
    eye = (0.0, 1.7, 0.0)
    aim_at = (3.8, 2.8, -3.0)
    # the spot sits just outside the glowing lantern (which would block it), on the beam's side
    out = g.normalize((aim_at[0] - lantern[0], 0.0, aim_at[2] - lantern[2]))
    beam_origin = g.add(lantern, g.scale(out, 1.45 * lantern_r + 0.08))  # clear of its bounding box
    parts.checks.assert_free("beam origin", beam_origin, 0.05)
    beam = g.sub(aim_at, beam_origin)
    b.add_light("beam", "spot", (1.0, 0.93, 0.78), 9000.0, translation=beam_origin, rotation=aim(beam),
                inner_cone=0.04, outer_cone=0.08)
    # distance from the eye to the beam's axis, and the beam's radius there
    d = g.normalize(beam)
    to_eye = g.sub(eye, beam_origin)
    along = g.dot(to_eye, d)
    miss = math.sqrt(max(0.0, g.dot(to_eye, to_eye) - along * along))
    radius = along * math.tan(0.08)
    assert radius < miss < radius + 4.0, "the beam passes %.2f m from the eye (radius %.2f)" % (miss, radius)
    print("  beam axis passes %.2f m from the eye, beam radius there %.2f m" % (miss, radius))
    parts.checks.assert_clear("beam leaves the lantern", beam_origin, aim_at)

    b.set_ambient(b.add_medium("sea_fog", scattering=0.035, absorption=0.003, anisotropy=0.55))

    target = (-2.0, 6.5, -22.0)
    yfov, aspect = 0.85, 4.0 / 3.0
    rot = g.quat_look_at(eye, target)
    b.add_camera("camera", yfov=yfov, aspect_ratio=aspect, translation=eye, rotation=rot)
    parts.checks.assert_free("camera", eye, 0.3)
    view = View(eye, rot, yfov, aspect)
    view.assert_in_view("lantern", lantern)
    f = view.film(aim_at)
    assert f is None or abs(f[0]) > 0.8, "the beam passes beside the viewer, not through the middle"
    assert parts.triangles < 50000, parts.triangles
    print("  %d triangles" % parts.triangles)
    return b.write(path)


def make_dusk_haze(path):
    """A causeway at dusk in coloured haze: extinction three times as high in blue as in red
    (scattering (0.012, 0.022, 0.04) /m). Near lamps light a bluish glow; the far lamps and
    the low sky at the end of the road come through reddened."""
    b = g.GltfBuilder("brume scenes/make_scenes.py")
    b.add_camera("camera", yfov=0.8, aspect_ratio=4.0 / 3.0, translation=(0.0, 1.6, 4.0))
    b.set_ambient(b.add_medium("dusk_haze", (0.012, 0.022, 0.04), 0.004, 0.4))
    m_road = b.add_material("road", base_color=(0.22, 0.22, 0.23))
    m_iron = b.add_material("lamp_iron", base_color=(0.05, 0.05, 0.055))
    m_sky = b.add_material("low_sky", base_color=(0.0, 0.0, 0.0), emissive=(1.0, 0.62, 0.42),
                           emissive_strength=1.2)
    # Road: 16 m wide, from z = 10 to z = -150, normal +Y.
    road = Geometry()
    road.append(g.quad((0.0, 0.0, -70.0), (0.0, 0.0, 80.0), (8.0, 0.0, 0.0)))
    assert g.triangle_normal(road.positions, road.indices, 0)[1] > 0
    b.add_node("road", mesh=b.add_mesh("road", road.positions, road.indices, normals=road.normals, uvs=road.uvs,
                                       material=m_road))
    # A low band of sky at the end of the road, facing the camera (+Z).
    sky = Geometry()
    sky.append(g.quad((0.0, 6.0, -150.0), (60.0, 0.0, 0.0), (0.0, 6.0, 0.0)))
    assert g.triangle_normal(sky.positions, sky.indices, 0)[2] > 0
    b.add_node("low_sky", mesh=b.add_mesh("low_sky", sky.positions, sky.indices, normals=sky.normals,
                                          uvs=sky.uvs, material=m_sky))
    # Lamp posts on both sides every 10 m: an iron pole and arm, a warm sphere light under it.
    posts = Geometry()
    lamps = []
    for k in range(9):
        z = -6.0 - 10.0 * k
        for side in (-1.0, 1.0):
            x = 4.6 * side
            posts.append(box_between((x - 0.06, 0.0, z - 0.06), (x + 0.06, 4.4, z + 0.06)))
            arm_lo, arm_hi = sorted((x, x - 1.1 * side))
            posts.append(box_between((arm_lo, 4.34, z - 0.04), (arm_hi, 4.42, z + 0.04)))
            lamps.append((x - 1.0 * side, 4.12, z))
    b.add_node("lamp_posts", mesh=b.add_mesh("lamp_posts", posts.positions, posts.indices, normals=posts.normals,
                                             uvs=posts.uvs, material=m_iron))
    for i, p in enumerate(lamps):
        # Clear of the arm above (bottom at 4.34) and of the pole.
        assert p[1] + 0.12 < 4.34 and abs(abs(p[0]) - 4.6) > 0.5
        b.add_light("lamp_%d" % i, "point", (1.0, 0.78, 0.5), 30.0, translation=p, radius=0.12)
    return b.write(path)


# ---------------------------------------------------------------------------------------------
# headlights.gltf

def make_headlights(path):
    """A car seen from the front on a foggy road at night. Its two headlights (spots) shine
    back along the road, slightly down and towards the viewer, who stands inside their cones
    near the right-hand edge of the road: in strongly forward-scattering fog (g = 0.85) the
    beams glow towards the camera. Street lamps beyond the car glow in the fog."""
    b = TexturedBuilder()
    parts = Parts(b)
    m_road = b.add_material("road", base_color=(0.15, 0.15, 0.15))
    m_verge = b.add_material("verge", base_color=(0.23, 0.27, 0.21))
    m_paint = b.add_material("road_paint", base_color=(0.7, 0.7, 0.68))
    m_car = b.add_material("car_paint", base_color=(0.42, 0.06, 0.05), metallic=0.25, roughness=0.35)
    m_glass = b.add_material("car_windows", base_color=(0.08, 0.09, 0.1), metallic=0.6, roughness=0.15)
    m_black = b.add_material("black_trim", base_color=(0.03, 0.03, 0.03))
    m_tyre = b.add_material("tyre", base_color=(0.025, 0.025, 0.025))
    m_iron = b.add_material("lamp_iron", base_color=(0.06, 0.06, 0.065))
    m_post = b.add_material("marker_post", base_color=(0.65, 0.65, 0.62))
    headlight_color = (0.92, 0.96, 1.0)
    m_lens = b.add_material("headlight_lens", base_color=(0.0, 0.0, 0.0), emissive=headlight_color,
                            emissive_strength=40.0)

    # ---- the road (x in [-3.5, 3.5], along z) and the verges beside it, all at y = 0
    road_w, z_near, z_far = 3.5, 12.0, -130.0
    zc, zh = 0.5 * (z_near + z_far), 0.5 * (z_near - z_far)
    road = g.quad((0.0, 0.0, zc), (0.0, 0.0, zh), (road_w, 0.0, 0.0))
    assert road[1][0][1] > 0.999
    parts.mesh("road", road, m_road, solid=False)
    verges = Geometry()
    for side in (-1.0, 1.0):
        verges.append(g.quad((side * (road_w + 30.0), 0.0, zc), (0.0, 0.0, zh), (30.0, 0.0, 0.0)))
    assert all(n[1] > 0.999 for n in verges.normals)
    parts.mesh("verges", (verges.positions, verges.normals, verges.uvs, verges.indices), m_verge,
               solid=False)
    # a dashed centre line and solid edge lines, 3 mm above the road
    lines = Geometry()
    for k in range(14):
        lines.append(g.quad((0.0, 0.003, 8.0 - 6.0 * k), (0.0, 0.0, 1.5), (0.06, 0.0, 0.0)))
    for side in (-1.0, 1.0):
        lines.append(g.quad((side * (road_w - 0.2), 0.003, zc), (0.0, 0.0, zh), (0.06, 0.0, 0.0)))
    assert all(n[1] > 0.999 for n in lines.normals)
    parts.mesh("road_lines", (lines.positions, lines.normals, lines.uvs, lines.indices), m_paint,
               solid=False)
    # white marker posts along both verges
    for k in range(7):
        z = 6.0 - 12.0 * k
        for side in (-1.0, 1.0):
            x = side * (road_w + 0.7)
            parts.box(m_post, (x - 0.06, -0.02, z - 0.06), (x + 0.06, 1.0, z + 0.06), "marker post")

    # ---- the car, in its right-hand lane, facing +Z (towards the viewer)
    cx, cz = -1.75, -16.0
    front = cz + 2.2
    parts.box(m_car, (cx - 0.88, 0.32, cz - 2.2), (cx + 0.88, 0.95, front), "body")
    parts.box(m_glass, (cx - 0.76, 0.95, cz - 1.35), (cx + 0.76, 1.42, cz + 0.55), "cabin")
    parts.box(m_car, (cx - 0.74, 1.42, cz - 1.25), (cx + 0.74, 1.48, cz + 0.45), "roof")
    parts.box(m_black, (cx - 0.92, 0.28, front - 0.1), (cx + 0.92, 0.48, front + 0.1), "bumper")
    parts.box(m_black, (cx - 0.36, 0.56, front - 0.05), (cx + 0.36, 0.8, front + 0.02), "grille")
    to_x = g.quat_axis_angle((0.0, 0.0, 1.0), -0.5 * math.pi)  # cylinder axis +Y -> +X
    assert abs(g.quat_rotate(to_x, (0.0, 1.0, 0.0))[0] - 1.0) < 1e-12
    tyre_r, tyre_w = 0.34, 0.24
    tyres = Geometry()
    for dx in (-0.8, 0.8):
        for dz in (-1.4, 1.4):
            centre = (cx + dx, tyre_r - 0.01, cz + dz)  # sunk 1 cm into the road
            tyres.append(transformed(cylinder((0.0, -0.5 * tyre_w, 0.0), tyre_r, tyre_r, tyre_w, 20),
                                     to_x, centre))
            parts.checks.solid(g.sub(centre, (0.5 * tyre_w, tyre_r, tyre_r)),
                               g.add(centre, (0.5 * tyre_w, tyre_r, tyre_r)), "tyre")
    parts.mesh("tyres", (tyres.positions, tyres.normals, tyres.uvs, tyres.indices), m_tyre, solid=False)
    # headlights: a black bezel and a glowing lens on the front, a spot just in front of each
    hl_y, hl_half_gap = 0.7, 0.7
    headlights = [(cx - hl_half_gap, hl_y, front + 0.06), (cx + hl_half_gap, hl_y, front + 0.06)]
    lenses, bezels = Geometry(), Geometry()
    for hx, hy, _hz in headlights:
        bezels.append(disc((hx, hy, front + 0.003), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), 0.14, 24))
        lenses.append(disc((hx, hy, front + 0.008), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), 0.1, 24))
    assert all(n[2] > 0.999 for n in lenses.normals + bezels.normals)
    parts.mesh("headlight_bezels", (bezels.positions, bezels.normals, bezels.uvs, bezels.indices), m_black,
               solid=False)
    parts.mesh("headlight_lenses", (lenses.positions, lenses.normals, lenses.uvs, lenses.indices), m_lens,
               solid=False)

    # ---- street lamps beyond the car: tapered pole, arm over the road, hood, warm sphere light
    lamp_color, lamp_intensity, lamp_radius = (1.0, 0.72, 0.42), 10.0, 0.1
    lamps = []
    for k, (px, pz) in enumerate(((4.4, -17.0), (-4.4, -30.0), (4.4, -43.0))):
        toward = -1.0 if px > 0 else 1.0
        lx = px + 1.1 * toward
        parts.mesh("lamp_pole_%d" % (k + 1), cylinder((px, -0.02, pz), 0.09, 0.06, 5.02, 12, cap_bottom=False),
                   m_iron)
        parts.box(m_iron, (min(px, lx) - 0.05, 4.92, pz - 0.04), (max(px, lx) + 0.05, 5.0, pz + 0.04), "arm")
        parts.box(m_iron, (lx - 0.2, 4.84, pz - 0.16), (lx + 0.2, 4.92, pz + 0.16), "hood")
        lamp = (lx, 4.7, pz)
        b.add_light("street_lamp_%d" % (k + 1), "point", lamp_color, lamp_intensity, translation=lamp,
                    radius=lamp_radius)
        parts.checks.assert_free("street lamp %d" % (k + 1), lamp, lamp_radius + 0.02)
        lamps.append(lamp)
    parts.flush({m_car: "car_body", m_glass: "car_cabin", m_black: "car_trim", m_post: "marker_posts",
                 m_iron: "lamp_irons"})

    # ---- the camera: eye height, near the right-hand edge of the road, 15 m in front of the car
    eye = (2.6, 1.6, 1.0)
    target = (-0.6, 1.75, -20.0)
    yfov, aspect = 0.7, 4.0 / 3.0
    rot = g.quat_look_at(eye, target)
    b.add_camera("camera", yfov=yfov, aspect_ratio=aspect, translation=eye, rotation=rot)
    parts.checks.assert_free("camera", eye, 0.3)
    view = View(eye, rot, yfov, aspect)

    # ---- the headlight spots: aimed straight back along the road and a little down (onto the
    # road some 9 m ahead); the viewer stands beside the road just outside both cones, so the
    # beams pass close by and the fog between glows forward towards the viewer
    inner, outer = 0.16, 0.24
    for k, hl in enumerate(headlights):
        parts.checks.assert_free("headlight %d" % (k + 1), hl, 0.05)
        axis = g.normalize((0.0, -0.08, 1.0))
        b.add_light("headlight_%d" % (k + 1), "spot", headlight_color, 120.0, translation=hl, rotation=aim(axis),
                    inner_cone=inner, outer_cone=outer)
        to_eye = g.normalize(g.sub(eye, hl))
        off = math.acos(max(-1.0, min(1.0, g.dot(axis, to_eye))))
        assert outer < off < outer + 0.15, "the camera is %.3f rad off headlight %d's axis (outer cone %g)" % (
            off, k + 1, outer)
        assert axis[1] < 0 and axis[2] > 0.9, "the headlight points back along the road and down"
        print("  headlight %d: the camera is %.3f rad off its axis; the axis meets the road %.1f m ahead" %
              (k + 1, off, hl[1] / -axis[1]))
        parts.checks.assert_clear("headlight %d reaches the camera" % (k + 1), hl, eye)
        view.assert_in_view("headlight %d" % (k + 1), hl)
    for k, lamp in enumerate(lamps):
        view.assert_in_view("street lamp %d" % (k + 1), lamp)
        parts.checks.assert_clear("camera sees street lamp %d" % (k + 1), eye, lamp)

    b.set_ambient(b.add_medium("road_fog", scattering=0.06, absorption=0.004, anisotropy=0.85))
    assert parts.triangles < 3000, parts.triangles
    print("  %d triangles" % parts.triangles)
    return b.write(path)


def make_fog_room(path):
    """Benchmark scene for samplers and single scattering: a closed room (6 x 3 x 10 m,
    Lambertian walls of albedo 0.5, normals inwards) in thin isotropic fog (scattering
    0.05 /m, absorption 0.005 /m), one point light near the ceiling, the camera at one end."""
    b = g.GltfBuilder("brume scenes/make_scenes.py")
    b.add_camera("camera", yfov=0.8, aspect_ratio=4.0 / 3.0, translation=(0.0, 1.5, 1.5))
    b.set_ambient(b.add_medium("fog", 0.05, 0.005, 0.0))
    m_wall = b.add_material("wall", base_color=(0.5, 0.5, 0.5), metallic=0.0, roughness=1.0)
    room = Geometry()
    # Half extents: x 3, y 1.5 (0 to 3), z 5 (-8 to 2); each quad's normal is cross(u, v).
    room.append(g.quad((0.0, 0.0, -3.0), (0.0, 0.0, 5.0), (3.0, 0.0, 0.0)))    # floor, +Y
    room.append(g.quad((0.0, 3.0, -3.0), (3.0, 0.0, 0.0), (0.0, 0.0, 5.0)))    # ceiling, -Y
    room.append(g.quad((0.0, 1.5, -8.0), (3.0, 0.0, 0.0), (0.0, 1.5, 0.0)))    # far wall, +Z
    room.append(g.quad((0.0, 1.5, 2.0), (0.0, 1.5, 0.0), (3.0, 0.0, 0.0)))     # near wall, -Z
    room.append(g.quad((-3.0, 1.5, -3.0), (0.0, 1.5, 0.0), (0.0, 0.0, 5.0)))   # left wall, +X
    room.append(g.quad((3.0, 1.5, -3.0), (0.0, 0.0, 5.0), (0.0, 1.5, 0.0)))    # right wall, -X
    inward = [(0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1), (1, 0, 0), (-1, 0, 0)]
    for k, n in enumerate(inward):
        got = g.triangle_normal(room.positions, room.indices, 2 * k)
        length = math.sqrt(sum(c * c for c in got))
        assert all(abs(got[i] / length - n[i]) < 1e-6 for i in range(3)), (k, got)
    b.add_node("room", mesh=b.add_mesh("room", room.positions, room.indices, normals=room.normals, uvs=room.uvs,
                                       material=m_wall))
    b.add_light("light", "point", (1.0, 0.9, 0.75), 30.0, translation=(0.8, 2.4, -4.0))
    return b.write(path)


def make_panel_bench(path):
    """Benchmark scene for area lights close to the view: open isotropic fog (scattering
    0.1 /m, absorption 0.01 /m) under a one-sided 1.0 m x 1.5 m ceiling panel (radiance 10,
    facing down). The camera is pitched down by half its field of view, so the top of the
    view is level, and the panel's plane runs 6 cm above it: the top rows graze the panel."""
    b = g.GltfBuilder("brume scenes/make_scenes.py")
    yfov, aspect, eye = 0.6, 1.5, (0.0, 1.5, 0.0)
    pitch = g.quat_axis_angle((1.0, 0.0, 0.0), -0.5 * yfov)
    b.add_camera("camera", yfov=yfov, aspect_ratio=aspect, translation=eye, rotation=pitch)
    top = g.quat_rotate(pitch, (0.0, math.tan(0.5 * yfov), -1.0))
    assert abs(top[1]) < 1e-9, "the top of the view is level"
    b.set_ambient(b.add_medium("fog", 0.1, 0.01, 0.0))
    m_panel = b.add_material("panel", base_color=(0.0, 0.0, 0.0), emissive=(1.0, 1.0, 1.0), emissive_strength=10.0)
    panel = g.quad((0.0, eye[1] + 0.06, -3.5), (0.5, 0.0, 0.0), (0.0, 0.0, 0.75))
    assert panel[1][0][1] < -0.999, "the panel faces down"
    b.add_node("panel", mesh=b.add_mesh("panel", *_pnui(panel), material=m_panel))
    return b.write(path)


def make_panel_room(path):
    """A foggy studio under a large ceiling panel (bundled gallery scene for area lights close
    to the fog): a room 7 m x 3.2 m x 9 m (x -3.5..3.5, y 0..3.2, z -8..1), grey walls
    (albedo 0.45), a darker floor, a table and two crates; a 2.4 m x 1.4 m softbox panel
    (radiance 6, warm white, facing down) 2 cm under the ceiling; a small cool strip light
    on the back wall; isotropic haze (scattering 0.12 /m, absorption 0.01 /m) fills the room."""
    b = g.GltfBuilder("brume scenes/make_scenes.py")
    W, H, Z0, Z1 = 3.5, 3.2, -8.0, 1.0
    eye = (1.6, 1.45, 0.3)
    target = (-0.3, 1.9, -4.2)
    b.add_camera("camera", yfov=0.9, aspect_ratio=1.5, translation=eye, rotation=g.quat_look_at(eye, target))
    b.set_ambient(b.add_medium("haze", 0.12, 0.01, 0.0))
    m_wall = b.add_material("wall", base_color=(0.45, 0.45, 0.45), metallic=0.0, roughness=1.0)
    m_floor = b.add_material("floor", base_color=(0.22, 0.2, 0.18), metallic=0.0, roughness=1.0)
    m_wood = b.add_material("wood", base_color=(0.42, 0.28, 0.16), metallic=0.0, roughness=1.0)
    zc, zh = 0.5 * (Z0 + Z1), 0.5 * (Z1 - Z0)
    room = Geometry()
    room.append(g.quad((0.0, H, zc), (W, 0.0, 0.0), (0.0, 0.0, zh)))           # ceiling, -Y
    room.append(g.quad((0.0, 0.5 * H, Z0), (W, 0.0, 0.0), (0.0, 0.5 * H, 0.0)))  # back wall, +Z
    room.append(g.quad((0.0, 0.5 * H, Z1), (0.0, 0.5 * H, 0.0), (W, 0.0, 0.0)))  # front wall, -Z
    room.append(g.quad((-W, 0.5 * H, zc), (0.0, 0.5 * H, 0.0), (0.0, 0.0, zh)))  # left wall, +X
    room.append(g.quad((W, 0.5 * H, zc), (0.0, 0.0, zh), (0.0, 0.5 * H, 0.0)))   # right wall, -X
    b.add_node("walls", mesh=b.add_mesh("walls", room.positions, room.indices, normals=room.normals,
                                        uvs=room.uvs, material=m_wall))
    floor = g.quad((0.0, 0.0, zc), (0.0, 0.0, zh), (W, 0.0, 0.0))                # floor, +Y
    assert floor[1][0][1] > 0.999
    b.add_node("floor", mesh=b.add_mesh("floor", *_pnui(floor), material=m_floor))
    furniture = Geometry()
    furniture.append(box_between((-1.2, 0.72, -4.9), (0.6, 0.78, -3.9)))      # table top
    for x in (-1.1, 0.5):
        for z in (-4.8, -4.0):
            furniture.append(box_between((x - 0.03, 0.0, z - 0.03), (x + 0.03, 0.72, z + 0.03)))
    furniture.append(box_between((1.6, 0.0, -6.6), (2.4, 0.8, -5.8)))         # crates
    furniture.append(box_between((1.8, 0.8, -6.4), (2.3, 1.3, -5.9)))
    b.add_node("furniture", mesh=b.add_mesh("furniture", furniture.positions, furniture.indices,
                                            normals=furniture.normals, uvs=furniture.uvs, material=m_wood))
    m_panel = b.add_material("softbox", base_color=(0.0, 0.0, 0.0), emissive=(1.0, 0.9, 0.78), emissive_strength=6.0)
    panel = g.quad((-0.3, H - 0.02, -4.4), (1.2, 0.0, 0.0), (0.0, 0.0, 0.7))
    assert panel[1][0][1] < -0.999, "the softbox faces down"
    b.add_node("softbox", mesh=b.add_mesh("softbox", *_pnui(panel), material=m_panel))
    m_strip = b.add_material("strip", base_color=(0.0, 0.0, 0.0), emissive=(0.6, 0.8, 1.0), emissive_strength=4.0)
    strip = g.quad((-2.2, 2.2, Z0 + 0.01), (0.9, 0.0, 0.0), (0.0, 0.04, 0.0))
    assert strip[1][0][2] > 0.999, "the strip faces into the room"
    b.add_node("strip", mesh=b.add_mesh("strip", *_pnui(strip), material=m_strip))
    return b.write(path)


def make_next_room(path):
    """Fog lit from the next room (bundled gallery scene for path guiding): the camera's room
    (x -2..2, y 0..3, z -8..1) has a doorway (1 m wide, 2.2 m high) in its left wall at
    z -5.5..-4.5; beyond it a second room (x -6..-2, z -8..-2) holds the only light, a warm
    sphere lamp (radius 0.1 m, 150 W/sr) hidden from the camera by the wall. Its light reaches
    the camera's room through the doorway, directly as a shaft in the fog and on the floor,
    and after bounces off the walls (grey 0.6) of both rooms. Walls are 0.15 m boxes; fog
    (scattering 0.1 /m, absorption 0.008 /m, g = 0.3) fills both rooms."""
    b = g.GltfBuilder("brume scenes/make_scenes.py")
    eye, target = (1.3, 1.6, 0.4), (-1.8, 1.1, -5.2)
    b.add_camera("camera", yfov=0.9, aspect_ratio=4.0 / 3.0, translation=eye, rotation=g.quat_look_at(eye, target))
    b.set_ambient(b.add_medium("fog", 0.1, 0.008, 0.3))
    m_wall = b.add_material("wall", base_color=(0.6, 0.6, 0.6), metallic=0.0, roughness=1.0)
    m_floor = b.add_material("floor", base_color=(0.3, 0.27, 0.24), metallic=0.0, roughness=1.0)
    m_wood = b.add_material("wood", base_color=(0.42, 0.28, 0.16), metallic=0.0, roughness=1.0)
    H, T = 3.0, 0.15
    door_z, door_h = (-5.5, -4.5), 2.2
    walls = Geometry()
    walls.append(box_between((-6.0 - T, 0.0, -8.0 - T), (2.0 + T, H, -8.0)))      # back wall (both rooms)
    walls.append(box_between((2.0, 0.0, -8.0), (2.0 + T, H, 1.0 + T)))            # right wall
    walls.append(box_between((-2.0 - T, 0.0, 1.0), (2.0, H, 1.0 + T)))            # front wall
    walls.append(box_between((-6.0 - T, 0.0, -8.0), (-6.0, H, -2.0)))             # next room's far wall
    walls.append(box_between((-6.0 - T, 0.0, -2.0), (-2.0 - T, H, -2.0 + T)))     # next room's front wall
    # The dividing wall, with the doorway.
    walls.append(box_between((-2.0 - T, 0.0, -8.0), (-2.0, H, door_z[0])))
    walls.append(box_between((-2.0 - T, 0.0, door_z[1]), (-2.0, H, 1.0)))
    walls.append(box_between((-2.0 - T, door_h, door_z[0]), (-2.0, H, door_z[1])))
    walls.append(g.quad((-2.0, H, -3.5), (4.2, 0.0, 0.0), (0.0, 0.0, 4.7)))     # ceiling, -Y (both rooms)
    assert walls.normals[-1][1] < -0.999
    b.add_node("walls", mesh=b.add_mesh("walls", walls.positions, walls.indices, normals=walls.normals,
                                        uvs=walls.uvs, material=m_wall))
    floor = g.quad((-2.0, 0.0, -3.5), (0.0, 0.0, 4.7), (4.2, 0.0, 0.0))         # floor, +Y
    assert floor[1][0][1] > 0.999
    b.add_node("floor", mesh=b.add_mesh("floor", *_pnui(floor), material=m_floor))
    furniture = Geometry()
    furniture.append(box_between((-5.0, 0.7, -7.0), (-3.6, 0.76, -6.0)))       # the next room's table
    for x in (-4.9, -3.7):
        for z in (-6.9, -6.1):
            furniture.append(box_between((x - 0.03, 0.0, z - 0.03), (x + 0.03, 0.7, z + 0.03)))
    furniture.append(box_between((0.4, 0.0, -6.8), (1.4, 0.9, -5.8)))          # a crate in the camera's room
    furniture.append(box_between((-1.2, 0.0, -2.6), (-0.5, 0.45, -1.9)))         # a low box
    b.add_node("furniture", mesh=b.add_mesh("furniture", furniture.positions, furniture.indices,
                                            normals=furniture.normals, uvs=furniture.uvs, material=m_wood))
    lamp = (-4.4, 2.3, -6.4)
    b.add_light("lamp", "point", (1.0, 0.82, 0.6), 150.0, translation=lamp, radius=0.1)
    # The lamp is hidden from the camera: the line between them meets the dividing wall's
    # plane outside the doorway.
    s_wall = (eye[0] + 2.0) / (eye[0] - lamp[0])
    z_wall = eye[2] + s_wall * (lamp[2] - eye[2])
    y_wall = eye[1] + s_wall * (lamp[1] - eye[1])
    assert not (door_z[0] < z_wall < door_z[1] and y_wall < door_h), (z_wall, y_wall)
    # ... and lights the camera room's floor through the doorway: the line from the lamp to
    # the floor at (-1, 0, -5) passes the doorway, above the table's edge.
    spot = (-1.0, 0.0, -5.0)
    def at_x(x):
        s = (x - lamp[0]) / (spot[0] - lamp[0])
        return tuple(lamp[i] + s * (spot[i] - lamp[i]) for i in range(3))
    _, y_door, z_door = at_x(-2.0)
    assert y_door < door_h and door_z[0] < z_door < door_z[1], (y_door, z_door)
    assert at_x(-3.6)[1] > 0.76
    return b.write(path)


def main():
    written = [
        make_street(os.path.join(HERE, "street.gltf")),
        # Thin fog, a point light close to the view rays: equi-angular sampling's home ground.
        make_fog_bench(os.path.join(HERE, "bench_thin_near.gltf"), 0.03, 0.003, (0.6, 1.8, -6.0), 20.0),
        # Dense fog, a distant light: free-flight sampling's home ground.
        make_fog_bench(os.path.join(HERE, "bench_dense_far.gltf"), 0.25, 0.01, (4.0, 4.0, -12.0), 60.0),
        # Strongly forward-scattering fog (g = 0.9), the light in view: product sampling's home ground.
        make_fog_bench(os.path.join(HERE, "bench_forward.gltf"), 0.05, 0.005, (0.6, 1.8, -6.0), 20.0,
                       anisotropy=0.9),
        # A closed fog room lit by one point light: samplers, single and multiple scattering.
        make_fog_room(os.path.join(HERE, "bench_fog_room.gltf")),
        # Open fog grazed by a large ceiling panel: area lights close to the view rays.
        make_panel_bench(os.path.join(HERE, "bench_panel.gltf")),
        make_panel_room(os.path.join(HERE, "panel_room.gltf")),
        # Fog lit through a doorway by a lamp in the next room: path guiding's case.
        make_next_room(os.path.join(HERE, "next_room.gltf")),
        # Lit-fog showcase scenes (README gallery)
        make_god_rays(os.path.join(HERE, "god_rays.gltf")),
        make_area_hall(os.path.join(HERE, "area_hall.gltf")),
        make_caustic(os.path.join(HERE, "caustic.gltf")),
        make_smoke_box(os.path.join(HERE, "smoke_box.gltf")),
        make_lighthouse(os.path.join(HERE, "lighthouse.gltf")),
        make_dusk_haze(os.path.join(HERE, "dusk_haze.gltf")),
        make_headlights(os.path.join(HERE, "headlights.gltf")),
    ]
    for path in written:
        print(os.path.relpath(path, os.getcwd()))


if __name__ == "__main__":
    main()
