#!/usr/bin/python3
"""Writes the glTF scenes of the stability suite (tests/stability/*.gltf): small scenes at the
edges where light-transport methods break down (a light on a camera ray or next to a surface,
extreme media, extreme anisotropy, odd lights, far coordinates, degenerate triangles).

Run: /usr/bin/python3 tests/stability/make_stability_scenes.py
Standard library only; the output is deterministic. tests/stability/README.md says what each
scene is for; the C++ tests (tests/stability/test_stability_*.cpp) render them at 16x12 and
compare every method with a reference. Where a test needs a scene's numbers
(a light position, an offset) they are duplicated there: change both together.
"""

import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "scenes"))

sys.dont_write_bytecode = True  # no __pycache__ next to the scenes
import gltfgen as g  # noqa: E402

GENERATOR = "brume tests/stability/make_stability_scenes.py"
ASPECT = 16.0 / 12.0  # the tests render 16x12
YFOV = 0.6

# The common fog: albedo 0.8, mildly forward.
FOG_S, FOG_A, FOG_G = 0.2, 0.05, 0.3


def out(name):
    return os.path.join(HERE, name)


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def builder(translation=(0.0, 0.0, 0.0), yfov=YFOV):
    """Camera at `translation` looking down -Z, +Y up."""
    b = g.GltfBuilder(GENERATOR)
    b.add_camera("camera", yfov=yfov, aspect_ratio=ASPECT, translation=translation)
    return b


def grey(b, albedo=0.5):
    return b.add_material("grey", base_color=(albedo,) * 3, metallic=0.0, roughness=1.0)


def emitter(b, radiance):
    return b.add_material("emitter", base_color=(0.0, 0.0, 0.0), metallic=0.0, roughness=1.0,
                          emissive=(radiance,) * 3)


def add_quad(b, name, center, u_half, v_half, normal, material):
    """A two-triangle rectangle whose front faces point along `normal` (asserted)."""
    pos, nrm, _uvs, idx = g.quad(center, u_half, v_half)
    for t in range(2):
        n = g.normalize(g.triangle_normal(pos, idx, t))
        assert all(abs(n[i] - normal[i]) < 1e-12 for i in range(3)), "quad faces %r" % (n,)
    b.add_node(name, mesh=b.add_mesh(name, pos, idx, normals=nrm, material=material))


def back_wall(b, z, material, half=(6.0, 4.5)):
    add_quad(b, "back_wall", (0.0, 0.0, z), (half[0], 0.0, 0.0), (0.0, half[1], 0.0), (0.0, 0.0, 1.0), material)


def add_fog_box(b, name, lo, hi, medium):
    """Invisible closed boundary of the box [lo, hi] enclosing `medium` (no material)."""
    size = g.sub(hi, lo)
    center = g.scale(g.add(lo, hi), 0.5)
    pos, _nrm, _uvs, idx = g.box(size, center)
    vol = g.signed_volume(pos, idx)
    assert abs(vol - size[0] * size[1] * size[2]) < 1e-6 * abs(vol), "box faces inward (volume %g)" % vol
    b.add_node(name, mesh=b.add_mesh(name, pos, idx, interior=medium))


def ambient_fog(b, scattering=FOG_S, absorption=FOG_A, anisotropy=FOG_G):
    b.set_ambient(b.add_medium("fog", scattering, absorption, anisotropy))


# ---------------------------------------------------------------------------------------------
# Lights in awkward places

def on_ray(name):
    """A point light exactly on the central camera ray: the image centre (film position 8, 6 of
    16x12) looks straight down -Z at it. No geometry."""
    b = builder()
    ambient_fog(b)
    b.add_light("light", "point", (1.0, 1.0, 1.0), 10.0, translation=(0.0, 0.0, -3.0))
    return b.write(out(name))


def segment_end(name):
    """Camera rays end on a wall that has lights right on it: a point light 1 cm in front of
    the wall and a one-sided 0.3 m quad light 1 mm in front of it, both facing the camera."""
    b = builder()
    ambient_fog(b)
    back_wall(b, -3.0, grey(b))
    b.add_light("light", "point", (1.0, 1.0, 1.0), 10.0, translation=(0.25, 0.15, -2.99))
    add_quad(b, "quad_light", (-0.4, -0.2, -2.999), (0.15, 0.0, 0.0), (0.0, 0.15, 0.0), (0.0, 0.0, 1.0),
             emitter(b, 5.0))
    return b.write(out(name))


def tiny_spot(name):
    """A spot light with a 0.5 degree outer cone (inner 0.25 degrees) crossing the view
    diagonally and landing on a grey floor in view."""
    b = builder()
    ambient_fog(b)
    apex, target = (-1.2, 0.6, -3.0), (0.6, -0.9, -3.4)
    d = g.normalize(g.sub(target, apex))
    rot = g.quat_look_dir(d)
    r = g.quat_rotate(rot, (0.0, 0.0, -1.0))
    assert all(abs(r[i] - d[i]) < 1e-12 for i in range(3)), "spot points along %r" % (r,)
    # glTF's spot falloff divides by max(0.001, cos inner - cos outer): for so narrow a cone
    # the peak attenuation is ((1 - cos outer) / 0.001)^2 = 1.45e-3, hence the intensity.
    b.add_light("spot", "spot", (1.0, 1.0, 1.0), 2.0e4, translation=apex, rotation=rot,
                inner_cone=math.radians(0.25), outer_cone=math.radians(0.5))
    add_quad(b, "floor", (0.0, -0.9, -4.0), (3.0, 0.0, 0.0), (0.0, 0.0, -3.0), (0.0, 1.0, 0.0), grey(b))
    return b.write(out(name))


def camera_in_beam(name):
    """The camera on the light subpaths' rays: a spot light in view, 0.5 degree outer cone,
    aimed exactly at the camera, so that every light subpath's first segment passes within
    3 cm of the pinhole (camera connections sample towards it at distances near 0). A grey wall
    behind the light."""
    b = builder()
    ambient_fog(b)
    back_wall(b, -6.0, grey(b))
    apex = (0.3, 0.2, -3.0)
    d = g.normalize(g.sub((0.0, 0.0, 0.0), apex))
    rot = g.quat_look_dir(d)
    r = g.quat_rotate(rot, (0.0, 0.0, -1.0))
    assert all(abs(r[i] - d[i]) < 1e-12 for i in range(3)), "spot points along %r" % (r,)
    # Peak attenuation 1.45e-3 as in tiny_spot.
    b.add_light("spot", "spot", (1.0, 1.0, 1.0), 2.0e4, translation=apex, rotation=rot,
                inner_cone=math.radians(0.25), outer_cone=math.radians(0.5))
    return b.write(out(name))


def directional(name, sun_node_inside):
    """Only a directional light, shining into a bounded fog box (vacuum outside, so that the
    light has a finite path through fog) above a grey floor outside the box. The light's node
    position does not matter physically; `sun_node_inside` puts it inside the fog box (as an
    exporter may), otherwise above the box."""
    b = builder()
    fog = b.add_medium("fog", 0.3, 0.05, 0.5)
    add_fog_box(b, "fog_box", (-2.0, -1.0, -6.0), (2.0, 2.0, -2.0), fog)
    add_quad(b, "floor", (0.0, -1.2, -4.0), (3.0, 0.0, 0.0), (0.0, 0.0, -3.0), (0.0, 1.0, 0.0), grey(b))
    d = g.normalize((0.4, -1.0, -0.3))
    rot = g.quat_look_dir(d)
    r = g.quat_rotate(rot, (0.0, 0.0, -1.0))
    assert all(abs(r[i] - d[i]) < 1e-12 for i in range(3))
    node = (0.0, 0.5, -4.0) if sun_node_inside else (0.0, 5.0, -4.0)
    b.add_light("sun", "directional", (1.0, 1.0, 1.0), 3.0, translation=node, rotation=rot)
    return b.write(out(name))


def blue_haze(name):
    """Coloured haze (scattering (0.02, 0.05, 0.2) /m, absorption 0.002, g = 0.3) in a fog box
    x in [-8, 8], y in [-1, 6], z in [-20, 1] (vacuum outside, so that sunlight enters it),
    over a grey ground at y = -1: a street lamp (point, 10 W/sr, warm white) at (1, 2, -6)
    and a sun (2 W/m^2) travelling along (0.3, -1, -0.5)."""
    b = builder()
    haze = b.add_medium("haze", (0.02, 0.05, 0.2), 0.002, 0.3)
    add_fog_box(b, "haze_box", (-8.0, -1.0, -20.0), (8.0, 6.0, 1.0), haze)
    add_quad(b, "ground", (0.0, -1.0, -9.5), (8.0, 0.0, 0.0), (0.0, 0.0, -10.5), (0.0, 1.0, 0.0), grey(b))
    b.add_light("lamp", "point", (1.0, 0.85, 0.6), 10.0, translation=(1.0, 2.0, -6.0))
    d = g.normalize((0.3, -1.0, -0.5))
    rot = g.quat_look_dir(d)
    b.add_light("sun", "directional", (1.0, 1.0, 1.0), 2.0, translation=(0.0, 10.0, -8.0), rotation=rot)
    return b.write(out(name))


def light_box_scene(b, offset):
    """A point light and a small sphere light inside a 2 m fog box (vacuum outside) above a grey
    floor outside the box, everything shifted by `offset`. Every coordinate is a multiple of
    1/16 so that the shifted scene is exactly the same scene in float32."""
    def at(p):
        q = g.add(p, offset)
        for c in q:
            assert f32(c) == c, "coordinate %r is not exact in float32" % (c,)
        return q
    fog = b.add_medium("fog", 0.5, 0.05, 0.3)
    lo, hi = at((-1.0, -1.0, -4.5)), at((1.0, 1.0, -2.5))
    add_fog_box(b, "fog_box", lo, hi, fog)
    add_quad(b, "floor", at((0.0, -1.25, -3.5)), (1.5, 0.0, 0.0), (0.0, 0.0, -1.5), (0.0, 1.0, 0.0), grey(b))
    b.add_light("light", "point", (1.0, 1.0, 1.0), 10.0, translation=at((0.1875, 0.3125, -3.375)))
    b.add_light("bulb", "point", (1.0, 1.0, 1.0), 4.0, translation=at((-0.375, -0.3125, -3.75)), radius=0.125)


def light_in_box(name):
    b = builder(yfov=0.7)
    light_box_scene(b, (0.0, 0.0, 0.0))
    return b.write(out(name))


# 1.005e5 m from the origin; every component is an integer, exact in float32.
FAR_OFFSET = (60000.0, 40000.0, -70000.0)


def far(name):
    """light_in_box, camera included, shifted by FAR_OFFSET (|offset| = 1.005e5 m)."""
    assert abs(math.sqrt(g.dot(FAR_OFFSET, FAR_OFFSET)) - 1.005e5) < 1e2
    b = builder(translation=FAR_OFFSET, yfov=0.7)
    light_box_scene(b, FAR_OFFSET)
    return b.write(out(name))


# ---------------------------------------------------------------------------------------------
# Extreme media

def dense(name):
    """sigma_t = 10/m in a scene 5 m deep (sigma_t x size = 50), albedo 0.8: a point light
    0.5 m in front of the camera (5 mean free paths), a grey wall at 5 m."""
    b = builder()
    ambient_fog(b, 8.0, 2.0, FOG_G)
    back_wall(b, -5.0, grey(b))
    b.add_light("light", "point", (1.0, 1.0, 1.0), 10.0, translation=(0.1, 0.05, -0.5))
    return b.write(out(name))


def thin(name):
    """sigma_t = 1e-6/m: a point light above a grey floor that fills the lower part of the view;
    the upper part sees only fog, out to infinity."""
    b = builder()
    ambient_fog(b, 0.8e-6, 0.2e-6, FOG_G)
    add_quad(b, "floor", (0.0, -1.0, -10.0), (8.0, 0.0, 0.0), (0.0, 0.0, -10.0), (0.0, 1.0, 0.0), grey(b))
    b.add_light("light", "point", (1.0, 1.0, 1.0), 10.0, translation=(0.3, 0.2, -3.0))
    return b.write(out(name))


def anisotropic(name, g_value, light):
    """HG g = g_value, a point light at `light`, a grey wall at 6 m."""
    b = builder()
    ambient_fog(b, FOG_S, FOG_A, g_value)
    back_wall(b, -6.0, grey(b))
    b.add_light("light", "point", (1.0, 1.0, 1.0), 10.0, translation=light)
    return b.write(out(name))


# ---------------------------------------------------------------------------------------------
# Degenerate triangles

def float_collinear_triangle(a, step):
    """Three points a, a + step, a + 2.5 step, collinear in exact arithmetic but not after
    rounding to float32 (so the renderer sees a sliver with a tiny area and an arbitrary
    normal). Asserted: the rounded triangle's area is positive and below 1e-6 |step|^2."""
    pts = [tuple(f32(a[i] + k * step[i]) for i in range(3)) for k in (0.0, 1.0, 2.5)]
    c = g.cross(g.sub(pts[1], pts[0]), g.sub(pts[2], pts[0]))
    area = 0.5 * math.sqrt(g.dot(c, c))
    assert 0 < area < 1e-6 * g.dot(step, step), "rounded sliver has area %g" % area
    return pts


def with_degenerates(pos, idx, a, step):
    """Appends to a mesh: a triangle with a repeated vertex, an exactly collinear one (points on
    an axis-aligned line) and a float32 sliver (float_collinear_triangle) near point a."""
    pos, idx = list(pos), list(idx)
    n = len(pos)
    idx += [0, 0, 1]  # repeated vertex: zero area
    pos += [a, g.add(a, (step[0], 0.0, 0.0)), g.add(a, (2.0 * step[0], 0.0, 0.0))]
    idx += [n, n + 1, n + 2]  # collinear along x: the cross product is exactly zero
    pos += float_collinear_triangle(g.add(a, (0.0, 0.01, 0.0)), step)
    idx += [n + 3, n + 4, n + 5]
    return pos, idx


def area_over_floor(name, degenerates=False):
    """A one-sided 1 m quad light (radiance 5) facing down at y = 1 over a grey floor at y = -1,
    in the common fog. With `degenerates`, both meshes also carry zero-area, exactly collinear
    and float32-sliver triangles (the light's are emissive too): otherwise the same scene."""
    b = builder(yfov=1.0)
    ambient_fog(b)
    pos, _n, _uv, idx = g.quad((0.0, 1.0, -3.0), (0.5, 0.0, 0.0), (0.0, 0.0, 0.5))
    assert abs(g.normalize(g.triangle_normal(pos, idx, 0))[1] + 1.0) < 1e-12
    if degenerates:
        pos, idx = with_degenerates(pos, idx, (-0.3, 0.999, -2.8), (0.1, 0.0003, -0.07))
    b.add_node("quad_light", mesh=b.add_mesh("quad_light", pos, idx, material=emitter(b, 5.0)))
    pos, _n, _uv, idx = g.quad((0.0, -1.0, -4.0), (3.0, 0.0, 0.0), (0.0, 0.0, -3.0))
    assert abs(g.normalize(g.triangle_normal(pos, idx, 0))[1] - 1.0) < 1e-12
    if degenerates:
        pos, idx = with_degenerates(pos, idx, (0.2, -0.999, -3.5), (0.2, 0.0005, 0.11))
    b.add_node("floor", mesh=b.add_mesh("floor", pos, idx, material=grey(b)))
    return b.write(out(name))


def zero_area_mesh():
    """Only degenerate triangles, in view: repeated vertex, exactly collinear, float32 sliver."""
    a = (-0.4, -0.1, -2.5)
    pos = [a, g.add(a, (0.3, 0.2, 0.0)), g.add(a, (0.0, 0.3, 0.0))]
    idx = [0, 1, 1]
    return with_degenerates(pos, idx, (0.1, 0.1, -2.5), (0.15, 0.05, 0.02))


def zero_area_emitter(name, with_point_light):
    """An emissive mesh of zero-area triangles only (radiance 5, double-sided), in view, in
    the common fog; with or without a point light that lights the scene."""
    b = builder()
    ambient_fog(b)
    m = b.add_material("emitter", base_color=(0.0, 0.0, 0.0), metallic=0.0, roughness=1.0,
                       emissive=(5.0, 5.0, 5.0), double_sided=True)
    pos, idx = zero_area_mesh()
    b.add_node("zero_area_light", mesh=b.add_mesh("zero_area_light", pos, idx, material=m))
    if with_point_light:
        b.add_light("light", "point", (1.0, 1.0, 1.0), 10.0, translation=(0.3, 0.2, -3.0))
    return b.write(out(name))


# ---------------------------------------------------------------------------------------------
# Large area lights close up (solid-angle sampling of emitters)

def panel_floor(b):
    add_quad(b, "floor", (0.0, -1.0, -4.0), (0.0, 0.0, 3.0), (3.0, 0.0, 0.0), (0.0, 1.0, 0.0), grey(b))


def camera_in_panel_plane(name):
    """A one-sided 2 m x 3 m panel (radiance 4, facing down) whose plane y = 0 holds the camera:
    the middle row of camera rays runs in the emitter's plane, grazing it edge-on; a floor."""
    b = builder()
    ambient_fog(b)
    add_quad(b, "panel", (1.3, 0.0, -2.5), (1.0, 0.0, 0.0), (0.0, 0.0, 1.5), (0.0, -1.0, 0.0), emitter(b, 4.0))
    panel_floor(b)
    return b.write(out(name))


def reflective_emitter(name):
    """Rays that start on the emitter: a 1.2 m panel (radiance 3, facing down, double-sided)
    that is also a grey diffuse reflector, 0.4 m above a floor, so that paths bounce off it
    and sample it from its own surface."""
    b = builder(translation=(0.0, 0.3, 0.0))
    ambient_fog(b)
    m = b.add_material("glowing_grey", base_color=(0.5, 0.5, 0.5), metallic=0.0, roughness=1.0,
                       emissive=(3.0, 3.0, 3.0), double_sided=True)
    add_quad(b, "panel", (0.0, -0.6, -3.0), (0.6, 0.0, 0.0), (0.0, 0.0, 0.6), (0.0, -1.0, 0.0), m)
    panel_floor(b)
    return b.write(out(name))


def huge_emitter(name):
    """A 2 km x 2 km ceiling (radiance 0.5, facing down) 1.5 m above the camera, over a floor:
    it subtends nearly a hemisphere from every point (solid-angle sampling falls back to area)."""
    b = builder()
    ambient_fog(b)
    add_quad(b, "sky_panel", (0.0, 1.5, -3.0), (1000.0, 0.0, 0.0), (0.0, 0.0, 1000.0), (0.0, -1.0, 0.0), emitter(b, 0.5))
    panel_floor(b)
    return b.write(out(name))


def main():
    written = [
        on_ray("on_ray.gltf"),
        segment_end("segment_end.gltf"),
        dense("dense.gltf"),
        thin("thin.gltf"),
        anisotropic("g_forward.gltf", 0.999, (0.3, 0.2, -3.0)),
        # Back-scattering: the light 1 m behind the camera, near the view axis.
        anisotropic("g_backward.gltf", -0.999, (0.1, 0.05, 1.0)),
        directional("directional.gltf", sun_node_inside=False),
        directional("directional_node_inside.gltf", sun_node_inside=True),
        blue_haze("blue_haze.gltf"),
        tiny_spot("tiny_spot.gltf"),
        camera_in_beam("camera_in_beam.gltf"),
        light_in_box("light_in_box.gltf"),
        far("far.gltf"),
        area_over_floor("area_over_floor.gltf"),
        area_over_floor("degenerate.gltf", degenerates=True),
        zero_area_emitter("zero_area_emitter.gltf", with_point_light=True),
        zero_area_emitter("zero_area_only.gltf", with_point_light=False),
        camera_in_panel_plane("camera_in_panel_plane.gltf"),
        reflective_emitter("reflective_emitter.gltf"),
        huge_emitter("huge_emitter.gltf"),
    ]
    for path in written:
        print(os.path.relpath(path, os.getcwd()))


if __name__ == "__main__":
    main()
