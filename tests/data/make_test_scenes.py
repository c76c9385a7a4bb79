#!/usr/bin/python3
"""Writes the glTF test scenes in tests/data/ (oracles for the renderer's tests).

Run: /usr/bin/python3 tests/data/make_test_scenes.py
The outputs are deterministic; tests/data/README.md says what each file is for. The geometry
and light parameters here are duplicated in the C++ tests (e.g. tests/test_pt_oracles.cpp):
change both together.
"""

import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "scenes"))

sys.dont_write_bytecode = True  # no __pycache__ next to the scenes
import gltfgen as g  # noqa: E402

# Furnace sphere: radius 2 about the origin, 48 segments around Y x 24 rings (2208 triangles).
FURNACE_RADIUS = 2.0
FURNACE_SEGMENTS = 48
FURNACE_RINGS = 24

# Single-scattering scenes
SINGLE_YFOV = 0.6
SINGLE_SCATTERING = 0.2
SINGLE_ABSORPTION = 0.05
SINGLE_G = 0.3
POINT_INTENSITY = 10.0


def out(name):
    return os.path.join(HERE, name)


def camera_at_origin(b, yfov):
    """Camera at the origin looking down -Z (identity rotation), square aspect."""
    b.add_camera("camera", yfov=yfov, aspect_ratio=1.0, translation=(0.0, 0.0, 0.0))


def inward_sphere(radius):
    """The furnace wall: closed UV sphere whose front (CCW) faces point at the centre.
    No NORMAL attribute: the renderer uses the exact geometric (flat) normals."""
    pos, _normals, _uvs, idx = g.uv_sphere(radius, FURNACE_SEGMENTS, FURNACE_RINGS, inward=True)
    # Checks: closed and consistently wound, every triangle's front normal points inward,
    # every vertex on the sphere.
    g.check_closed(idx)
    for t in range(len(idx) // 3):
        n = g.triangle_normal(pos, idx, t)
        centroid = g.scale(g.add(g.add(pos[idx[3 * t]], pos[idx[3 * t + 1]]), pos[idx[3 * t + 2]]), 1.0 / 3.0)
        assert g.dot(n, centroid) < 0, "triangle %d faces outward" % t
    vol = g.signed_volume(pos, idx)
    ball = 4.0 / 3.0 * math.pi * radius ** 3
    assert -ball < vol < -0.95 * ball, "signed volume %g: not an inward sphere" % vol
    for p in pos:
        assert abs(math.sqrt(g.dot(p, p)) - radius) < 1e-12
    return pos, idx


def furnace(name, ambient, wall_albedo, wall_emission, scattering=1.0, absorption=0.0, anisotropy=0.5,
            medium_name="fog", density=None, node_translation=None, node_rotation=None, emission=None,
            blackbody=None):
    """wall_albedo and wall_emission: a grey value or an RGB triple. density: a density grid
    for the medium (BRUME_media "density"); emission: the medium's (BRUME_media "emission");
    node_*: the wall node's transform; blackbody: the medium's "blackbody"."""
    rgb = lambda v: tuple(v) if isinstance(v, (tuple, list)) else (v,) * 3
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, 1.0)
    fog = b.add_medium(medium_name, scattering=scattering, absorption=absorption, anisotropy=anisotropy,
                       density=density, emission=emission, blackbody=blackbody)
    wall = b.add_material("wall", base_color=rgb(wall_albedo), metallic=0.0, roughness=1.0,
                          emissive=rgb(wall_emission))
    pos, idx = inward_sphere(FURNACE_RADIUS)
    if ambient:
        b.set_ambient(fog)
        mesh = b.add_mesh("wall", pos, idx, material=wall)
    else:
        mesh = b.add_mesh("wall", pos, idx, material=wall, interior=fog)
    b.add_node("wall", mesh=mesh, translation=node_translation, rotation=node_rotation)
    return b.write(out(name))


def single(name, light_pos, scattering=SINGLE_SCATTERING, absorption=SINGLE_ABSORPTION,
           anisotropy=SINGLE_G, radius=None):
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, SINGLE_YFOV)
    b.set_ambient(b.add_medium("fog", scattering, absorption, anisotropy))
    b.add_light("light", "point", (1.0, 1.0, 1.0), POINT_INTENSITY, translation=light_pos, radius=radius)
    return b.write(out(name))


def single_spot(name, cycles=False):
    """cycles: a 60 degree spot (outer cone pi/6) with Cycles' profile, blend 0.15 (test_spot_profile)."""
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, SINGLE_YFOV)
    b.set_ambient(b.add_medium("fog", SINGLE_SCATTERING, SINGLE_ABSORPTION, SINGLE_G))
    # -90 degrees about +X maps local -Z onto world -Y: straight down.
    down = g.quat_axis_angle((1.0, 0.0, 0.0), -0.5 * math.pi)
    d = g.quat_rotate(down, (0.0, 0.0, -1.0))
    assert abs(d[0]) < 1e-12 and abs(d[1] + 1.0) < 1e-12 and abs(d[2]) < 1e-12
    if cycles:
        b.add_light("spot", "spot", (1.0, 1.0, 1.0), 30.0, translation=(0.0, 1.5, -3.0), rotation=down,
                    inner_cone=0.45, outer_cone=math.pi / 6)
        b.lights[-1]["extras"] = {"spotProfile": "cycles", "spotBlend": 0.15}
    else:
        b.add_light("spot", "spot", (1.0, 1.0, 1.0), 30.0, translation=(0.0, 1.5, -3.0), rotation=down,
                    inner_cone=0.2, outer_cone=0.4)
    return b.write(out(name))


def empty(name):
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, 0.8)
    return b.write(out(name))


def quad_light_fog(name, scattering=SINGLE_SCATTERING, absorption=SINGLE_ABSORPTION):
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, 1.0)  # the quad (seen 0.28-0.38 rad above the axis) is in view
    b.set_ambient(b.add_medium("fog", scattering, absorption, SINGLE_G))
    emitter = b.add_material("emitter", base_color=(0.0, 0.0, 0.0), metallic=0.0, roughness=1.0,
                             emissive=(5.0, 5.0, 5.0))
    # 1 m x 1 m at y = 1, centred on (0, 1, -3); u x v = (0.5, 0, 0) x (0, 0, 0.5) points to -Y.
    pos, nrm, uvs, idx = g.quad((0.0, 1.0, -3.0), (0.5, 0.0, 0.0), (0.0, 0.0, 0.5))
    for t in range(2):
        n = g.normalize(g.triangle_normal(pos, idx, t))
        assert abs(n[0]) < 1e-12 and abs(n[1] + 1.0) < 1e-12 and abs(n[2]) < 1e-12
    assert all(abs(p[1] - 1.0) == 0 for p in pos)
    b.add_node("quad_light", mesh=b.add_mesh("quad_light", pos, idx, normals=nrm, material=emitter))
    return b.write(out(name))


def area_quad(name):
    """Quadrature oracle: a one-sided 1 m quad light, radiance 5, 1 m above the top of the
    view (camera yfov 0.6), facing down, in single-scattering fog. See test_pt_area_oracles."""
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, SINGLE_YFOV)
    b.set_ambient(b.add_medium("fog", SINGLE_SCATTERING, SINGLE_ABSORPTION, SINGLE_G))
    emitter = b.add_material("emitter", base_color=(0.0, 0.0, 0.0), metallic=0.0, roughness=1.0,
                             emissive=(5.0, 5.0, 5.0))
    pos, nrm, uvs, idx = g.quad((0.0, 2.0, -3.0), (0.5, 0.0, 0.0), (0.0, 0.0, 0.5))
    for t in range(2):
        n = g.normalize(g.triangle_normal(pos, idx, t))
        assert abs(n[1] + 1.0) < 1e-12
    b.add_node("quad_light", mesh=b.add_mesh("quad_light", pos, idx, normals=nrm, material=emitter))
    return b.write(out(name))


def many_lights(name, extended=True):
    """Quadrature oracle for picks by where a connection starts (light_selection.h): a point
    light near the camera (intensity 10), a bright one out of view far off (intensity 1000:
    97% of the power, so power's picks and the picks by position differ 30x for the others),
    single_spot's spot (intensity 30), a sphere light below the view (intensity 10, radius
    0.4: a hittable light, steered along segments, large enough that phase sampling's hits
    on it carry weight) and area_quad's one-sided quad (radiance 40
    here, two triangles) in single-scattering fog. No light can shadow another on a connection
    from a camera ray (the quad is above the view and every other light below it, the sphere
    below every such connection), so the reference is the sum of each light's. See
    test_light_selection. Without `extended`, the three point-like lights alone: the
    bidirectional tracer's single scattering is then split between the path tracer and light
    tracing (one_event_split.h)."""
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, SINGLE_YFOV)
    b.set_ambient(b.add_medium("fog", SINGLE_SCATTERING, SINGLE_ABSORPTION, SINGLE_G))
    b.add_light("near", "point", (1.0, 1.0, 1.0), POINT_INTENSITY, translation=(0.3, 0.2, -1.5))
    b.add_light("bright", "point", (1.0, 1.0, 1.0), 1000.0, translation=(-12.0, -0.5, -20.0))
    down = g.quat_axis_angle((1.0, 0.0, 0.0), -0.5 * math.pi)
    b.add_light("spot", "spot", (1.0, 1.0, 1.0), 30.0, translation=(0.0, 1.5, -3.0), rotation=down,
                inner_cone=0.2, outer_cone=0.4)
    if not extended:
        return b.write(out(name))
    b.add_light("low", "point", (1.0, 1.0, 1.0), POINT_INTENSITY, translation=(0.0, -1.5, -3.0), radius=0.4)
    emitter = b.add_material("emitter", base_color=(0.0, 0.0, 0.0), metallic=0.0, roughness=1.0,
                             emissive=(5.0, 5.0, 5.0), emissive_strength=8.0)
    pos, nrm, uvs, idx = g.quad((0.0, 2.0, -3.0), (0.5, 0.0, 0.0), (0.0, 0.0, 0.5))
    b.add_node("quad_light", mesh=b.add_mesh("quad_light", pos, idx, normals=nrm, material=emitter))
    return b.write(out(name))


TOP_SLOPE = math.tan(0.5 * SINGLE_YFOV)  # the top of the view: y = TOP_SLOPE * (-z)


def panel_close_geometry():
    """A 1.0 m x 1.5 m panel parallel to the top plane of the view (camera at the origin, yfov
    0.6, square image), 4 cm above it, centred over z = -3 and facing into the view; the
    quadrature oracle of test_pt_area_oracles / test_bdpt_oracles uses the same numbers."""
    n_top = g.normalize((0.0, 1.0, TOP_SLOPE))          # out of the view through its top plane
    along = g.normalize((0.0, TOP_SLOPE, -1.0))         # up the top plane, away from the camera
    center = g.add((0.0, 3.0 * TOP_SLOPE, -3.0), g.scale(n_top, 0.04))
    return center, (0.5, 0.0, 0.0), g.scale(along, 0.75), g.scale(n_top, -1.0)


def area_rectangles_close(name):
    """Quadrature oracle for large area lights close to the view rays (one-sided rectangles,
    radiance 3, in single-scattering fog): the ceiling panel of panel_close_geometry, and a
    1.6 m x 1.2 m window in the plane x = 0.55 beside the camera (z from -0.1 to -1.7, facing
    -x), 2.5 cm outside the view at its far end."""
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, SINGLE_YFOV)
    b.set_ambient(b.add_medium("fog", SINGLE_SCATTERING, SINGLE_ABSORPTION, SINGLE_G))
    emitter = b.add_material("emitter", base_color=(0.0, 0.0, 0.0), metallic=0.0, roughness=1.0,
                             emissive=(3.0, 3.0, 3.0))
    center, u, v, normal = panel_close_geometry()
    # quad's front normal is u x v: order the spans so that it is `normal`
    if g.dot(g.cross(u, v), normal) < 0:
        u, v = v, u
    panel = checked_quad(center, u, v, normal)
    window = checked_quad((0.55, 0.0, -0.9), (0.0, 0.0, 0.8), (0.0, 0.6, 0.0), (-1.0, 0.0, 0.0))
    assert 0.55 - TOP_SLOPE * 1.7 > 0.02, "the window is outside the view"
    for part, label in ((panel, "panel"), (window, "window")):
        pos, nrm, uvs, idx = part
        b.add_node(label, mesh=b.add_mesh(label, pos, idx, normals=nrm, material=emitter))
    return b.write(out(name))


# ---------------------------------------------------------------------------------------------
# Small scenes for comparing the bidirectional path tracer with the path tracer (rendered at
# tiny resolutions with a few hundred samples per pixel).

def checked_quad(center, u_half, v_half, normal):
    """g.quad with an assertion that both triangles' front faces point along `normal`."""
    pos, nrm, uvs, idx = g.quad(center, u_half, v_half)
    for t in range(2):
        n = g.normalize(g.triangle_normal(pos, idx, t))
        assert all(abs(n[i] - normal[i]) < 1e-12 for i in range(3)), "quad faces %r" % (n,)
    return pos, nrm, uvs, idx


def add_quad(b, name, center, u_half, v_half, normal, material):
    pos, nrm, _uvs, idx = checked_quad(center, u_half, v_half, normal)
    b.add_node(name, mesh=b.add_mesh(name, pos, idx, normals=nrm, material=material))


def add_fog_box(b, name, lo, hi, medium):
    """Invisible closed boundary (no material, no NORMAL) of the box [lo, hi] enclosing `medium`."""
    size = g.sub(hi, lo)
    center = g.scale(g.add(lo, hi), 0.5)
    pos, _nrm, _uvs, idx = g.box(size, center)
    vol = g.signed_volume(pos, idx)
    assert abs(vol - size[0] * size[1] * size[2]) < 1e-9, "box faces inward (volume %g)" % vol
    for p in pos:
        assert all(abs(p[i] - lo[i]) < 1e-12 or abs(p[i] - hi[i]) < 1e-12 for i in range(3))
    b.add_node(name, mesh=b.add_mesh(name, pos, idx, interior=medium))


def add_glass_material(b, name, ior):
    """Smooth glass: KHR_materials_transmission 1 + KHR_materials_ior (gltfgen has no helper)."""
    m = b.add_material(name, base_color=(1.0, 1.0, 1.0), metallic=0.0, roughness=0.0)
    b.materials[m]["extensions"] = {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                    "KHR_materials_ior": {"ior": float(ior)}}
    b.extensions_used.update(("KHR_materials_transmission", "KHR_materials_ior"))
    return m


def bdpt_quad_fogbox(name):
    """Fog only inside a 2 m box (vacuum around it) lit by a one-sided 0.6 m quad light near the
    box's top; a grey floor under the box catches the light that leaves it."""
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, 0.7)  # every pixel's ray enters the box's front face (z = -2.5)
    fog = b.add_medium("fog", scattering=0.5, absorption=0.05, anisotropy=0.3)
    add_fog_box(b, "fog_box", (-1.0, -1.0, -4.5), (1.0, 1.0, -2.5), fog)
    emitter = b.add_material("emitter", base_color=(0.0, 0.0, 0.0), metallic=0.0, roughness=1.0,
                             emissive=(1.0, 1.0, 1.0), emissive_strength=4.0)
    # 0.6 m x 0.6 m at y = 0.9 (0.1 m below the box top), facing -Y.
    add_quad(b, "quad_light", (0.0, 0.9, -3.5), (0.3, 0.0, 0.0), (0.0, 0.0, 0.3), (0.0, -1.0, 0.0),
             emitter)
    grey = b.add_material("floor", base_color=(0.5, 0.5, 0.5), metallic=0.0, roughness=1.0)
    # 3 m x 3 m at y = -1.2, facing +Y.
    add_quad(b, "floor", (0.0, -1.2, -3.5), (1.5, 0.0, 0.0), (0.0, 0.0, -1.5), (0.0, 1.0, 0.0), grey)
    return b.write(out(name))


# Transparent emitters (Material::transparent, as Cycles' lights): test_transparent_emitters.
PANEL_RADIANCE = 2.0
WALL_ALBEDO = 0.5
WALL_Z = -4.0
LAMP_POS = (0.0, 0.0, -1.0)
LAMP_INTENSITY = 3.0


def transparent_emitter(b, name, emissive, camera_visible=True):
    m = b.add_material(name, base_color=(0.0, 0.0, 0.0), metallic=0.0, roughness=1.0, emissive=emissive)
    b.materials[m]["extras"] = {"transparent": True}
    if not camera_visible:
        b.materials[m]["extras"]["cameraVisible"] = False
    return m


def transparent_panel(name, camera_visible):
    """Closed form, in vacuum: a transparent panel (radiance PANEL_RADIANCE towards the camera,
    filling the view at z = -2) in front of a diffuse wall (z = WALL_Z, albedo WALL_ALBEDO) lit
    through the panel by a point light at LAMP_POS between the camera and the panel. The panel
    emits away from the wall, so a pixel sees PANEL_RADIANCE (if the camera sees the panel) plus
    the wall's albedo/pi x E."""
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, SINGLE_YFOV)
    panel = transparent_emitter(b, "panel", (PANEL_RADIANCE,) * 3, camera_visible)
    add_quad(b, "panel", (0.0, 0.0, -2.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), panel)
    wall = b.add_material("wall", base_color=(WALL_ALBEDO,) * 3, metallic=0.0, roughness=1.0)
    add_quad(b, "wall", (0.0, 0.0, WALL_Z), (5.0, 0.0, 0.0), (0.0, 5.0, 0.0), (0.0, 0.0, 1.0), wall)
    b.add_light("lamp", "point", (1.0, 1.0, 1.0), LAMP_INTENSITY, translation=LAMP_POS)
    return b.write(out(name))


def transparent_panels_fog(name):
    """Fog over a grey floor, a point light above a transparent panel that the camera sees
    (facing down, so the lamp shines through it), and a second one the camera does not see,
    facing the view from the right: bdpt against pt (test_transparent_emitters)."""
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, 0.8)
    b.set_ambient(b.add_medium("fog", 0.3, 0.05, 0.3))
    seen = transparent_emitter(b, "seen", (3.0, 3.0, 3.0))
    unseen = transparent_emitter(b, "unseen", (2.0, 2.0, 2.0), camera_visible=False)
    add_quad(b, "seen", (0.0, 0.3, -3.0), (0.4, 0.0, 0.0), (0.0, 0.0, 0.4), (0.0, -1.0, 0.0), seen)
    add_quad(b, "unseen", (0.6, -0.1, -2.5), (0.0, 0.0, 0.3), (0.0, 0.3, 0.0), (-1.0, 0.0, 0.0), unseen)
    grey = b.add_material("floor", base_color=(0.5, 0.5, 0.5), metallic=0.0, roughness=1.0)
    add_quad(b, "floor", (0.0, -1.0, -3.0), (2.0, 0.0, 0.0), (0.0, 0.0, -2.0), (0.0, 1.0, 0.0), grey)
    b.add_light("lamp", "point", (1.0, 1.0, 1.0), 4.0, translation=(0.0, 1.2, -3.0))
    return b.write(out(name))


WINDOW_CENTER = (-2.0, 1.8, -2.5)
WINDOW_HALF = 0.5
WINDOW_SUN_DIR = (1.0, -0.6, 0.2)  # direction of travel, normalized below


def bdpt_window_fog(name):
    """A closed grey room (x in [-2, 2], y in [0, 3], z in [-5, 0], walls facing inward) with a
    1 m square window in the left wall, filled with fog (bounded just inside the walls, vacuum
    outside), lit only by a directional light shining in through the window."""
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    b.add_camera("camera", yfov=1.0, aspect_ratio=1.0, translation=(0.0, 1.5, -0.2))
    fog = b.add_medium("fog", scattering=0.15, absorption=0.01, anisotropy=0.5)
    add_fog_box(b, "fog_box", (-1.99, 0.01, -4.99), (1.99, 2.99, -0.01), fog)
    grey = b.add_material("wall", base_color=(0.5, 0.5, 0.5), metallic=0.0, roughness=1.0)
    add_quad(b, "floor", (0.0, 0.0, -2.5), (2.0, 0.0, 0.0), (0.0, 0.0, -2.5), (0.0, 1.0, 0.0), grey)
    add_quad(b, "ceiling", (0.0, 3.0, -2.5), (2.0, 0.0, 0.0), (0.0, 0.0, 2.5), (0.0, -1.0, 0.0), grey)
    add_quad(b, "back_wall", (0.0, 1.5, -5.0), (2.0, 0.0, 0.0), (0.0, 1.5, 0.0), (0.0, 0.0, 1.0), grey)
    add_quad(b, "front_wall", (0.0, 1.5, 0.0), (-2.0, 0.0, 0.0), (0.0, 1.5, 0.0), (0.0, 0.0, -1.0), grey)
    add_quad(b, "right_wall", (2.0, 1.5, -2.5), (0.0, 0.0, 2.5), (0.0, 1.5, 0.0), (-1.0, 0.0, 0.0), grey)
    # Left wall (x = -2, facing +X) as four quads around the window y in [1.3, 2.3], z in [-3, -2].
    wy0, wy1 = WINDOW_CENTER[1] - WINDOW_HALF, WINDOW_CENTER[1] + WINDOW_HALF
    wz0, wz1 = WINDOW_CENTER[2] - WINDOW_HALF, WINDOW_CENTER[2] + WINDOW_HALF
    plus_x = (1.0, 0.0, 0.0)

    def left_piece(piece, y0, y1, z0, z1):
        add_quad(b, "left_wall_" + piece, (-2.0, 0.5 * (y0 + y1), 0.5 * (z0 + z1)),
                 (0.0, 0.0, -0.5 * (z1 - z0)), (0.0, 0.5 * (y1 - y0), 0.0), plus_x, grey)

    left_piece("below", 0.0, wy0, -5.0, 0.0)
    left_piece("above", wy1, 3.0, -5.0, 0.0)
    left_piece("back", wy0, wy1, -5.0, wz0)
    left_piece("front", wy0, wy1, wz1, 0.0)
    # The sun: local -Z onto the direction of travel.
    d = g.normalize(WINDOW_SUN_DIR)
    rot = g.quat_look_dir(d)
    r = g.quat_rotate(rot, (0.0, 0.0, -1.0))
    assert all(abs(r[i] - d[i]) < 1e-12 for i in range(3)), "sun points along %r" % (r,)
    # Directional: the position does not matter; put the node outside the window, on the beam axis.
    b.add_light("sun", "directional", (1.0, 0.95, 0.9), 5.0,
                translation=g.sub(WINDOW_CENTER, g.scale(d, 2.0)), rotation=rot)
    return b.write(out(name))


def bdpt_glass_sphere(name, sphere_light_radius=None):
    """A smooth glass sphere in ambient fog under a spot light that focuses a caustic on the
    grey floor below it."""
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    eye, target = (0.0, 0.6, 0.0), (0.0, -0.2, -3.0)
    look = g.quat_look_at(eye, target)
    f = g.quat_rotate(look, (0.0, 0.0, -1.0))
    want = g.normalize(g.sub(target, eye))
    assert all(abs(f[i] - want[i]) < 1e-12 for i in range(3))
    b.add_camera("camera", yfov=0.8, aspect_ratio=1.0, translation=eye, rotation=look)
    b.set_ambient(b.add_medium("fog", scattering=0.1, absorption=0.01, anisotropy=0.3))
    glass = add_glass_material(b, "glass", 1.5)
    center, radius = (0.0, 0.3, -3.0), 0.5
    pos, nrm, _uvs, idx = g.uv_sphere(radius, 32, 16, center=center)
    g.check_closed(idx)
    vol = g.signed_volume(pos, idx)
    ball = 4.0 / 3.0 * math.pi * radius ** 3
    assert 0.95 * ball < vol < ball, "signed volume %g: not an outward sphere" % vol
    b.add_node("glass_sphere", mesh=b.add_mesh("glass_sphere", pos, idx, normals=nrm, material=glass))
    # Spot straight down (-90 degrees about +X: local -Z onto world -Y).
    down = g.quat_axis_angle((1.0, 0.0, 0.0), -0.5 * math.pi)
    d = g.quat_rotate(down, (0.0, 0.0, -1.0))
    assert abs(d[0]) < 1e-12 and abs(d[1] + 1.0) < 1e-12 and abs(d[2]) < 1e-12
    if sphere_light_radius:
        # The path tracer can only reach the light through the glass if it has a size.
        b.add_light("bulb", "point", (1.0, 1.0, 1.0), 40.0, translation=(0.0, 2.5, -3.0),
                    radius=sphere_light_radius)
    else:
        b.add_light("spot", "spot", (1.0, 1.0, 1.0), 40.0, translation=(0.0, 2.5, -3.0), rotation=down,
                    inner_cone=0.15, outer_cone=0.25)
    grey = b.add_material("floor", base_color=(0.6, 0.6, 0.6), metallic=0.0, roughness=1.0)
    add_quad(b, "floor", (0.0, -0.6, -3.0), (2.0, 0.0, 0.0), (0.0, 0.0, -2.0), (0.0, 1.0, 0.0), grey)
    return b.write(out(name))


# ---- heterogeneous media (density grids, .vdb written with Debian's python3-openvdb) --------

def write_grid(name, lo, hi, voxel, field):
    """A float grid "density" with voxel (i, j, k) at world voxel * (i, j, k), for i in
    [lo, hi] per axis (inclusive), valued field(x, y, z) (numpy arrays); zeros stay inactive."""
    import numpy as np
    import pyopenvdb as vdb
    lo, hi = np.array(lo), np.array(hi)
    idx = np.indices(tuple(hi - lo + 1)) + lo[:, None, None, None]
    x, y, z = idx * voxel
    values = np.asarray(field(x, y, z), dtype=np.float32)
    assert values.min() >= 0 and np.isfinite(values).all(), name
    grid = vdb.FloatGrid()
    grid.name = "density"
    grid.copyFromArray(values, ijk=tuple(int(v) for v in lo), tolerance=0)
    grid.transform = vdb.createLinearTransform(voxelSize=voxel)
    vdb.write(out(name), grids=[grid])
    return out(name)


def write_fire(name):
    """A small fire (the Blender round trip fire_grid): grids "density" (smoke: a plume rising
    around and above a flame, 0 to about 1.5) and "temperature" (the flame: up to 2, in units Blender's
    Temperature input scales to kelvin), 24 x 24 x 32 voxels of 0.05 m, z up, the flame's base
    at the origin."""
    import numpy as np
    import pyopenvdb as vdb
    lo = np.array((-12, -12, 0))
    idx = np.indices((24, 24, 32)) + lo[:, None, None, None]
    x, y, z = idx * 0.05
    r2 = x * x + y * y
    flame = 2.0 * np.exp(-r2 / 0.03 - (z - 0.4) ** 2 / 0.1)
    plume = 1.5 * np.exp(-r2 / (0.04 + 0.1 * z)) / (1.0 + np.exp(-(z - 0.35) / 0.1))
    grids = []
    for gname, field in (("density", plume), ("temperature", flame)):
        values = np.where(field > 1e-3, field, 0.0).astype(np.float32)
        grid = vdb.FloatGrid()
        grid.name = gname
        grid.copyFromArray(values, ijk=tuple(int(v) for v in lo), tolerance=0)
        grid.transform = vdb.createLinearTransform(voxelSize=0.05)
        grids.append(grid)
    vdb.write(out(name), grids=grids)
    return out(name)


def write_sparse_blocks(name):
    """A sparse grid "density" (voxel 0.05): two 8³ blocks of value 0.5 + (i + j + k) / 100,
    at index (0, 0, 0) and (2000, 0, 0), and an active tile of 0.25 filling the 128³ internal
    node at (4096, 0, 0): a box of 4224 × 128 × 128 voxels (69 million) holding 1024 voxels
    and one tile (the sparse storage's test, test_density_grid.cpp)."""
    import numpy as np
    import pyopenvdb as vdb
    grid = vdb.FloatGrid()
    grid.name = "density"
    block = np.fromfunction(lambda i, j, k: 0.5 + (i + j + k) / 100.0, (8, 8, 8)).astype(np.float32)
    grid.copyFromArray(block, ijk=(0, 0, 0), tolerance=0)
    grid.copyFromArray(block, ijk=(2000, 0, 0), tolerance=0)
    grid.fill((4096, 0, 0), (4223, 127, 127), 0.25, active=True)
    grid.transform = vdb.createLinearTransform(voxelSize=0.05)
    vdb.write(out(name), grids=[grid])
    return out(name)


def furnace_field(x, y, z):
    """Strongly varying, with empty regions: a product of sines (0 to 4 /m) cut to zero on
    one side of a slanted plane, plus a dense blob (8 /m) off the centre."""
    import numpy as np
    waves = 4.0 * (np.sin(2.1 * x + 0.3) * np.cos(1.7 * y) * np.sin(2.9 * z + 1.0)) ** 2
    waves = np.where(np.sin(1.3 * x + 0.5 * y) > -0.3, waves, 0.0)
    blob = 8.0 * np.exp(-((x - 0.5) ** 2 + (y - 0.3) ** 2 + (z + 1.0) ** 2) / 0.1)
    return waves + blob


def furnace_grid(name, scattering, node_translation=None, node_rotation=None, ambient=True):
    """The furnace (walls emit 1, albedo 0) filled with a non-absorbing grid medium: radiance
    exactly 1. Bounded: the grid is placed by the wall mesh's node (moved and turned)."""
    return furnace(name, ambient, wall_albedo=0.0, wall_emission=1.0, scattering=scattering, medium_name="smoke",
                   density={"uri": "furnace_grid.vdb", "grid": "density", "scale": 1.0},
                   node_translation=node_translation, node_rotation=node_rotation)


# Glowing furnaces (test_emission): walls of albedo 0.5 emitting 0.5, a medium that scatters,
# absorbs and emits as much as it absorbs (emission = absorption): radiance exactly 1.
def furnace_glowing(name, ambient=True, scattering=0.6, absorption=0.4, grid=False, node_translation=None,
                    node_rotation=None):
    rgb = lambda v: list(v) if isinstance(v, (tuple, list)) else [float(v)] * 3
    density = {"uri": "furnace_grid.vdb", "grid": "density", "scale": 0.5} if grid else None
    # With a grid: scattering, absorption and emission all in proportion to the one grid.
    emission = dict(density, rgb=rgb(absorption)) if grid else absorption
    return furnace(name, ambient, wall_albedo=0.5, wall_emission=0.5, scattering=scattering, absorption=absorption,
                   anisotropy=0.4, medium_name="glow", density=density, emission=emission,
                   node_translation=node_translation, node_rotation=node_rotation)


def furnace_blackbody(name):
    """The glowing furnace with blackbody emission (test_emission): a temperature grid of 2500 K
    everywhere in the sphere (temperature_uniform.vdb, value 1 over [-2.5, 2.5]^3, scale 2500);
    scattering 0.6, absorption 0.4. The test sets the tint to 0.4 / e(2500 K), so that the
    emission equals the absorption and the radiance is 1."""
    return furnace(name, True, wall_albedo=0.5, wall_emission=0.5, scattering=0.6, absorption=0.4, anisotropy=0.4,
                   medium_name="glow", blackbody={"uri": "temperature_uniform.vdb", "grid": "density",
                                                  "scale": 2500.0, "intensity": 1.0})


# The emitting box (test_emission): black walls around an absorbing medium that emits e:
# L = e/σa·(1 − exp(−σa·d)), d the distance to the wall. Emission 0.3, 0.5, 0.2 over
# absorption 0.2, 0.6, 1.4 (a coloured medium).
EMITTING = ((0.3, 0.5, 0.2), (0.2, 0.6, 1.4))


def emitting_sphere(name):
    return furnace(name, ambient=True, wall_albedo=0.0, wall_emission=0.0, scattering=0.0, absorption=EMITTING[1],
                   anisotropy=0.0, medium_name="glow", emission=EMITTING[0])


def glow_in_fog(name):
    """A glowing grid in fog (test_emission): furnace_grid.vdb (scattering 2, absorption 1,
    emission (3, 1.2, 0.3) per unit density) in an invisible box over the grid's extent
    [-2.2, 2.2]^3, its node scaled by 0.15 (a 0.66 m cube) and moved to (0, 0, -3); in ambient
    fog (scattering 0.15, absorption 0.02, g 0.3) above a grey floor at y = -0.6; the camera
    (yfov 0.9) at the origin."""
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, 0.9)
    b.set_ambient(b.add_medium("fog", 0.15, 0.02, 0.3))
    grid = {"uri": "furnace_grid.vdb", "grid": "density", "scale": 1.0}
    glow = b.add_medium("glow", 2.0, 1.0, 0.3, density=grid, emission=dict(grid, rgb=[3.0, 1.2, 0.3]))
    pos, _nrm, _uvs, idx = g.box((4.4, 4.4, 4.4), (0.0, 0.0, 0.0))
    assert g.signed_volume(pos, idx) > 0
    b.add_node("glow_box", mesh=b.add_mesh("glow_box", pos, idx, interior=glow), translation=(0.0, 0.0, -3.0),
               scale=(0.15, 0.15, 0.15))
    floor = b.add_material("floor", base_color=(0.5, 0.5, 0.5), metallic=0.0, roughness=1.0)
    pos, nrm, _uvs, idx = g.quad((0.0, -0.6, -3.0), (3.0, 0.0, 0.0), (0.0, 0.0, -3.0))
    if g.triangle_normal(pos, idx, 0)[1] < 0:
        pos, nrm, _uvs, idx = g.quad((0.0, -0.6, -3.0), (0.0, 0.0, -3.0), (3.0, 0.0, 0.0))
    assert g.triangle_normal(pos, idx, 0)[1] > 0, "the floor faces up"
    b.add_node("floor", mesh=b.add_mesh("floor", pos, idx, normals=nrm, material=floor))
    return b.write(out(name))


# The absorbing ramp (test_heterogeneous): density 0.6 + 0.25 x + 0.1 y inside the box
# [-1.5, 1.5]^2 x [-3, -1], absorption 1 per unit density, in front of a backdrop of radiance 1.
RAMP = (0.6, 0.25, 0.1)


def absorbing_ramp(name):
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, 0.6)  # every camera ray crosses the box front to back (half-angle 0.3 < atan(1.5/3))
    ramp = b.add_medium("ramp", scattering=0.0, absorption=1.0, anisotropy=0.0,
                        density={"uri": "ramp.vdb", "grid": "density"})
    add_fog_box(b, "ramp_box", (-1.5, -1.5, -3.0), (1.5, 1.5, -1.0), ramp)
    backdrop = b.add_material("backdrop", base_color=(0.0, 0.0, 0.0), metallic=0.0, roughness=1.0,
                              emissive=(1.0, 1.0, 1.0))
    pos, nrm, uvs, idx = g.quad((0.0, 0.0, -4.0), (3.0, 0.0, 0.0), (0.0, 3.0, 0.0))
    for t in range(2):
        assert g.triangle_normal(pos, idx, t)[2] > 0, "the backdrop faces the camera"
    b.add_node("backdrop", mesh=b.add_mesh("backdrop", pos, idx, normals=nrm, material=backdrop))
    return b.write(out(name))


# Single scattering in a density gradient (test_heterogeneous): density 1 + 0.35 y inside the
# box [-2.5, 2.5] x [-2, 2] x [-6, -0.5], the single-scattering fog's coefficients per unit
# density, a point light at (0.3, 0.2, -3). Every camera ray leaves through the back face.
GRADIENT = (1.0, 0.35)


def single_gradient(name):
    b = g.GltfBuilder("brume tests/data/make_test_scenes.py")
    camera_at_origin(b, SINGLE_YFOV)
    fog = b.add_medium("fog", SINGLE_SCATTERING, SINGLE_ABSORPTION, SINGLE_G,
                       density={"uri": "gradient.vdb", "grid": "density"})
    add_fog_box(b, "fog_box", (-2.5, -2.0, -6.0), (2.5, 2.0, -0.5), fog)
    b.add_light("light", "point", (1.0, 1.0, 1.0), POINT_INTENSITY, translation=(0.3, 0.2, -3.0))
    return b.write(out(name))


def main():
    written = [
        furnace("furnace_ambient.gltf", ambient=True, wall_albedo=0.0, wall_emission=1.0),
        furnace("furnace_bounded.gltf", ambient=False, wall_albedo=0.0, wall_emission=1.0),
        furnace("furnace_albedo.gltf", ambient=True, wall_albedo=0.5, wall_emission=0.5),
        # Coloured media (test_chromatic): a non-absorbing fog whose channels differ 4x inside
        # coloured walls (exact answer 1), and a purely absorbing one (exact answer
        # exp(-sigma_a * distance to the wall)).
        furnace("furnace_chromatic.gltf", ambient=True, wall_albedo=(0.2, 0.5, 0.8),
                wall_emission=(0.8, 0.5, 0.2), scattering=(0.5, 1.0, 2.0), anisotropy=-0.3),
        furnace("furnace_absorbing.gltf", ambient=True, wall_albedo=0.0, wall_emission=1.0,
                scattering=0.0, absorption=(0.1, 0.4, 1.2), anisotropy=0.0),
        single("single_near.gltf", (0.3, 0.2, -3.0)),
        single("single_behind.gltf", (0.5, 0.0, 2.0)),
        single("single_side.gltf", (3.0, 1.0, -2.0)),
        single("single_chromatic.gltf", (0.3, 0.2, -3.0), scattering=(0.3, 0.2, 0.1),
               absorption=(0.02, 0.05, 0.1), anisotropy=-0.4),
        single_spot("single_spot.gltf"),
        single_spot("single_spot_cycles.gltf", cycles=True),
        empty("empty.gltf"),
        quad_light_fog("quad_light_fog.gltf"),
        # Strongly coloured fog (extinction 0.12 to 1.3 /m, ratio 11) for the MIS weight checker
        # and the single-scattering quadrature.
        quad_light_fog("quad_light_fog_chromatic.gltf", scattering=(0.1, 0.4, 1.2), absorption=(0.02, 0.05, 0.1)),
        single("single_chromatic_strong.gltf", (0.3, 0.2, -3.0), scattering=(0.1, 0.4, 1.2),
               absorption=(0.02, 0.05, 0.1), anisotropy=0.3),
        single("sphere_light_fog.gltf", (0.3, 0.2, -3.0), radius=0.25),
        # Sphere light partly in view (test_pt_area_oracles).
        single("area_sphere.gltf", (0.8, 0.5, -3.0), radius=0.3),
        area_quad("area_quad.gltf"),
        # Five lights of three kinds (test_light_selection).
        many_lights("many_lights.gltf"),
        many_lights("many_points.gltf", extended=False),
        # Large one-sided rectangles a few centimetres from the view rays (solid-angle sampling).
        area_rectangles_close("area_rectangles_close.gltf"),
        # Dense fog (mean free path 0.4 m, light 3 m away) and a light exactly on the central
        # camera ray of an odd-sized image (D = 0 for equi-angular sampling).
        single("single_dense.gltf", (0.3, 0.2, -3.0), scattering=2.0, absorption=0.5),
        single("single_on_ray.gltf", (0.0, 0.0, -3.0)),
        # Forward-scattering fog (g = 0.9, the issue on product sampling) with the light in
        # view, and a back-scattering one (g = -0.7) around a sphere light.
        single("single_forward.gltf", (0.3, 0.2, -3.0), anisotropy=0.9),
        single("area_sphere_back.gltf", (0.8, 0.5, -3.0), radius=0.3, anisotropy=-0.7),
        # Bidirectional vs unidirectional path tracing (test_bdpt*): small, everything lit.
        bdpt_quad_fogbox("bdpt_quad_fogbox.gltf"),
        # Transparent emitters, seen and not seen by the camera (test_transparent_emitters).
        transparent_panel("transparent_panel.gltf", camera_visible=True),
        transparent_panel("transparent_panel_unseen.gltf", camera_visible=False),
        transparent_panels_fog("transparent_panels_fog.gltf"),
        bdpt_window_fog("bdpt_window_fog.gltf"),
        bdpt_glass_sphere("bdpt_glass_sphere.gltf"),
        bdpt_glass_sphere("bdpt_glass_sphere_bulb.gltf", sphere_light_radius=0.1),
        # Heterogeneous media: the grids (1 voxel beyond their boxes, where trilinear
        # interpolation is exactly linear) and the scenes.
        write_grid("furnace_grid.vdb", (-22, -22, -22), (22, 22, 22), 0.1, furnace_field),
        furnace_grid("furnace_grid_ambient.gltf", 1.0),
        furnace_grid("furnace_grid_bounded.gltf", 1.0, node_translation=(0.2, -0.1, 0.15),
                     node_rotation=g.quat_axis_angle((0.0, 1.0, 0.0), 0.45), ambient=False),
        furnace_grid("furnace_grid_chromatic.gltf", (0.5, 1.0, 2.0)),
        write_grid("ramp.vdb", (-17, -17, -32), (17, 17, -8), 0.1,
                   lambda x, y, z: RAMP[0] + RAMP[1] * x + RAMP[2] * y + 0.0 * z),
        absorbing_ramp("absorbing_ramp.gltf"),
        write_grid("gradient.vdb", (-11, -9, -25), (11, 9, -1), 0.25,
                   lambda x, y, z: GRADIENT[0] + GRADIENT[1] * y + 0.0 * x + 0.0 * z),
        single_gradient("single_gradient.gltf"),
        write_sparse_blocks("sparse_blocks.vdb"),
        # Emissive media (test_emission).
        furnace_glowing("furnace_glowing.gltf"),
        furnace_glowing("furnace_glowing_bounded.gltf", ambient=False),
        furnace_glowing("furnace_glowing_chromatic.gltf", scattering=(0.3, 0.8, 1.6), absorption=(0.5, 0.3, 0.1)),
        furnace_glowing("furnace_glowing_grid.gltf", ambient=False, grid=True, node_translation=(0.2, -0.1, 0.15),
                        node_rotation=g.quat_axis_angle((0.0, 1.0, 0.0), 0.45)),
        write_grid("temperature_uniform.vdb", (-10, -10, -10), (10, 10, 10), 0.25, lambda x, y, z: 1.0 + 0.0 * x),
        furnace_blackbody("furnace_blackbody.gltf"),
        write_fire("fire.vdb"),
        emitting_sphere("emitting_sphere.gltf"),
        glow_in_fog("glow_in_fog.gltf"),
    ]
    for path in written:
        print(os.path.relpath(path, os.getcwd()))


if __name__ == "__main__":
    main()
