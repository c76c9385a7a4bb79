# Builds the round-trip test scenes in Blender and saves them as .blend files (no binary .blend
# is kept in the repository: this script is the source).
#
#   blender -b --factory-startup -P tests/blender/make_scenes.py -- OUTDIR [--width W --height H
#           --samples N --threads T] [NAME ...]
#
# Names: fog_point, spot_cube, spot_wide, sun_window, area_fog, glass_fog, glow_box, vdb_volume,
# fire_grid (the round-trip scenes), fire_smoke (fire_grid without its lamp: the fire alone
# lights the smoke; for equal-time measurements, docs/results.md), area_visible (an area light
# in the frame over back-scattering fog: a measured difference, docs/blender.md), slit_room (a
# closed fog room lit only through a narrow slit by a lamp outside; for equal-time
# measurements, docs/results.md) and
# bad_volume (an unsupported volume node: the bad-input test). Without names: all of them.
# Every scene is set up for a comparison with brume: Cycles with a box pixel filter 1 px wide,
# every bounce type at max_bounces, no clamping, no light threshold, no adaptive sampling, no
# denoising, no glossy filter, the Standard view transform, a fixed seed, 32-bit linear EXR.
import math
import os
import sys

import bpy

SCENES = ["fog_point", "spot_cube", "spot_wide", "sun_window", "area_fog", "glass_fog", "glow_box", "vdb_volume",
          "fire_grid", "fire_smoke", "area_visible", "slit_room", "bad_volume"]
DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "data")


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    opts = {"width": 64, "height": 48, "samples": 128, "threads": 1, "bounces": 3}
    names, out, i = [], None, 0
    while i < len(argv):
        a = argv[i]
        if a.startswith("--"):
            opts[a[2:]] = int(argv[i + 1])
            i += 2
            continue
        if out is None:
            out = a
        else:
            names.append(a)
        i += 1
    if out is None:
        raise SystemExit("usage: ... -- OUTDIR [--width W --height H --samples N --threads T --bounces B] [NAME ...]")
    return out, names or SCENES, opts


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return bpy.context.scene


def cycles_settings(sc, o):
    sc.render.engine = "CYCLES"
    c = sc.cycles
    c.device = "CPU"
    c.samples = o["samples"]
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = 1
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.max_bounces = o["bounces"]
    for name in ("diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces"):
        setattr(c, name, o["bounces"])
    c.transparent_max_bounces = 64
    sc.render.threads_mode = "FIXED"
    sc.render.threads = o["threads"]
    sc.render.resolution_x = o["width"]
    sc.render.resolution_y = o["height"]
    sc.render.resolution_percentage = 100
    sc.render.use_persistent_data = False
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0
    im = sc.render.image_settings
    im.file_format = "OPEN_EXR"
    im.color_depth = "32"
    im.color_mode = "RGB"
    im.exr_codec = "ZIP"


def black_world(sc, name="world"):
    w = bpy.data.worlds.new(name)
    sc.world = w
    w.use_nodes = True
    w.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    w.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    return w


def material(name, kind, **k):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    if kind == "diffuse":
        n = nt.nodes.new("ShaderNodeBsdfDiffuse")
        n.inputs["Color"].default_value = k["color"] + (1,)
        nt.links.new(n.outputs[0], out.inputs["Surface"])
    elif kind == "glass":
        n = nt.nodes.new("ShaderNodeBsdfGlass")
        n.distribution = "SHARP"
        n.inputs["Color"].default_value = (1, 1, 1, 1)
        n.inputs["IOR"].default_value = k["ior"]
        nt.links.new(n.outputs[0], out.inputs["Surface"])
    return m


def volume_nodes(nt, out_socket, spec):
    """spec: ('principled', color, density, absorption_color, g[, emission_color, emission_strength]) |
    ('scatter', color, density, g) | ('absorb', color, density) | ('emission', color, strength) |
    ('add', a, b) | other node idname (unsupported)."""
    kind = spec[0]
    if kind == "principled":
        n = nt.nodes.new("ShaderNodeVolumePrincipled")
        n.inputs["Color"].default_value = spec[1] + (1,)
        n.inputs["Density"].default_value = spec[2]
        n.inputs["Absorption Color"].default_value = spec[3] + (1,)
        n.inputs["Anisotropy"].default_value = spec[4]
        if len(spec) > 5:
            n.inputs["Emission Color"].default_value = spec[5] + (1,)
            n.inputs["Emission Strength"].default_value = spec[6]
    elif kind == "emission":
        n = nt.nodes.new("ShaderNodeEmission")
        n.inputs["Color"].default_value = spec[1] + (1,)
        n.inputs["Strength"].default_value = spec[2]
    elif kind == "scatter":
        n = nt.nodes.new("ShaderNodeVolumeScatter")
        n.inputs["Color"].default_value = spec[1] + (1,)
        n.inputs["Density"].default_value = spec[2]
        n.inputs["Anisotropy"].default_value = spec[3]
    elif kind == "absorb":
        n = nt.nodes.new("ShaderNodeVolumeAbsorption")
        n.inputs["Color"].default_value = spec[1] + (1,)
        n.inputs["Density"].default_value = spec[2]
    elif kind == "add":
        n = nt.nodes.new("ShaderNodeAddShader")
        volume_nodes(nt, n.inputs[0], spec[1])
        volume_nodes(nt, n.inputs[1], spec[2])
    else:
        n = nt.nodes.new(kind)
    nt.links.new(n.outputs[0], out_socket)
    return n


def world_volume(sc, spec):
    w = black_world(sc, "fog")
    volume_nodes(w.node_tree, w.node_tree.nodes["World Output"].inputs["Volume"], spec)
    return w


def volume_material(name, spec):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    volume_nodes(nt, out.inputs["Volume"], spec)
    m.cycles.homogeneous_volume = True
    return m


def volume_object(sc, name, vdb, scale, location, mat):
    """A Volume object of tests/data/<vdb>, uniformly scaled, with a heterogeneous volume
    material; Cycles ray-marches it a tenth of a voxel a step."""
    vol = bpy.data.volumes.new(name)
    vol.filepath = os.path.join(DATA, vdb)
    obj = bpy.data.objects.new(name, vol)
    sc.collection.objects.link(obj)
    obj.scale = (scale, scale, scale)
    obj.location = location
    mat.cycles.homogeneous_volume = False
    obj.data.materials.append(mat)
    sc.cycles.volume_step_rate = 0.1
    return obj


def link(obj, mat=None, name=None):
    if name:
        obj.name = name
        obj.data.name = name
    if mat is not None:
        obj.data.materials.clear()
        obj.data.materials.append(mat)
    return obj


def plane(name, size, loc, mat, rot=(0, 0, 0)):
    bpy.ops.mesh.primitive_plane_add(size=size, location=loc, rotation=rot)
    return link(bpy.context.object, mat, name)


def cube(name, size, loc, mat, scale=(1, 1, 1)):
    bpy.ops.mesh.primitive_cube_add(size=size, location=loc, scale=scale)
    return link(bpy.context.object, mat, name)


def sphere(name, radius, loc, mat):
    bpy.ops.mesh.primitive_uv_sphere_add(radius=radius, location=loc, segments=48, ring_count=24)
    o = link(bpy.context.object, mat, name)
    bpy.ops.object.shade_flat()
    return o


def wall_with_hole(sc, name, mat, y0, y1, z0, z1):
    """The 6 x 3 m wall at x = -3 (y in [-3, 3], z in [0, 3]) with a hole at y in [y0, y1], z in [z0, z1]."""
    import bmesh
    me = bpy.data.meshes.new(name)
    bm = bmesh.new()
    def quad(ya, yb, za, zb):
        v = [bm.verts.new((-3, y, z)) for y, z in ((ya, za), (ya, zb), (yb, zb), (yb, za))]
        bm.faces.new(v)
    quad(-3, y0, 0, 3)
    quad(y1, 3, 0, 3)
    quad(y0, y1, 0, z0)
    quad(y0, y1, z1, 3)
    bm.to_mesh(me)
    bm.free()
    ob = bpy.data.objects.new(name, me)
    sc.collection.objects.link(ob)
    me.materials.append(mat)


def camera(sc, loc, target, lens=35.0):
    cam = bpy.data.cameras.new("camera")
    cam.lens = lens
    cam.sensor_fit = "AUTO"
    o = bpy.data.objects.new("camera", cam)
    sc.collection.objects.link(o)
    o.location = loc
    d = [t - l for t, l in zip(target, loc)]
    import mathutils
    o.rotation_euler = mathutils.Vector(d).to_track_quat("-Z", "Y").to_euler()
    sc.camera = o
    return o


def light(sc, name, kind, loc, power, color=(1, 1, 1), rot=(0, 0, 0), **k):
    ld = bpy.data.lights.new(name, kind)
    ld.energy = power
    ld.color = color
    if kind in ("POINT", "SPOT"):
        ld.shadow_soft_size = k.get("radius", 0.0)
    if kind == "SPOT":
        ld.spot_size = k["spot_size"]
        ld.spot_blend = k["spot_blend"]
    if kind == "SUN":
        ld.angle = 0.0
    if kind == "AREA":
        ld.shape = k["shape"]
        ld.size = k["size"]
        ld.size_y = k.get("size_y", k["size"])
    o = bpy.data.objects.new(name, ld)
    sc.collection.objects.link(o)
    o.location = loc
    o.rotation_euler = rot
    return o


def build(name, o):
    sc = reset()
    cycles_settings(sc, o)
    grey = material("grey", "diffuse", color=(0.6, 0.6, 0.6))
    if name == "fog_point":
        # World fog (Volume Scatter + Volume Absorption through Add Shader) and a point light.
        world_volume(sc, ("add", ("scatter", (0.9, 0.8, 0.7), 0.12, 0.3), ("absorb", (0.7, 0.8, 0.9), 0.05)))
        plane("floor", 20, (0, 0, 0), grey)
        cube("block", 1.0, (0.8, 0.5, 0.5), material("red", "diffuse", color=(0.7, 0.2, 0.1)))
        light(sc, "lamp", "POINT", (-0.5, 0.0, 2.0), 300.0, (1.0, 0.9, 0.8))
        camera(sc, (0, -6, 2.0), (0, 0, 1.0))
    elif name in ("spot_cube", "spot_wide"):
        # A Principled Volume cube (no surface: a pure medium) under a spot, no world fog: a
        # narrow one (25 degrees), or a 60 degree one with a wide blend, where Cycles' cos(theta)
        # profile matters (glTF's would be 3.9 % brighter in the mean).
        black_world(sc)
        plane("floor", 20, (0, 0, 0), grey)
        cube("smoke", 1.6, (0, 0, 1.2), volume_material(
            "smoke", ("principled", (0.8, 0.6, 0.4), 1.2, (0.3, 0.3, 0.6), 0.5)))
        power, size, blend = (3000.0, 25.0, 0.1) if name == "spot_cube" else (1000.0, 60.0, 0.15)
        light(sc, "spot", "SPOT", (0.0, 0.0, 4.5), power, spot_size=math.radians(size), spot_blend=blend)
        camera(sc, (0, -6, 2.5), (0, 0, 1.0))
    elif name == "sun_window":
        # A room with a window; sunlight through it into a fog box that fills the room.
        black_world(sc)
        wall = material("wall", "diffuse", color=(0.5, 0.5, 0.5))
        plane("floor", 6, (0, 0, 0), wall)
        plane("ceiling", 6, (0, 0, 3), wall, rot=(math.pi, 0, 0))
        plane("back", 6, (0, 3, 1.5), wall, rot=(math.pi / 2, 0, 0))
        plane("right", 6, (3, 0, 1.5), wall, rot=(0, -math.pi / 2, 0))
        # The window wall at x = -3 (normal +x) with a 1.2 x 1.0 hole at y in [-0.6, 0.6], z in [1.2, 2.2].
        wall_with_hole(sc, "window_wall", wall, -0.6, 0.6, 1.2, 2.2)
        cube("room_fog", 1.0, (0.0, 0.0, 1.5), volume_material("room_fog", ("scatter", (1.0, 1.0, 1.0), 0.15, 0.4)),
             scale=(2.95, 2.95, 1.45))
        # Sun from -x, above: travels along (+0.8, +0.1, -0.6) roughly.
        light(sc, "sun", "SUN", (-5, 0, 5), 8.0, (1.0, 0.95, 0.85), rot=(0.0, -math.radians(55.0), math.radians(-8.0)))
        camera(sc, (2.6, -2.6, 1.4), (-1.5, 0.8, 1.2), lens=20.0)
    elif name == "slit_room":
        # A closed room (6 x 6 x 3 m, grey walls) full of fog, lit only through a vertical slit
        # (0.1 x 1.5 m) in its wall at x = -3 by a point lamp 1.5 m outside: most of the light
        # that reaches the camera has bounced off the walls or scattered more than once.
        black_world(sc)
        wall = material("wall", "diffuse", color=(0.6, 0.6, 0.6))
        plane("floor", 6, (0, 0, 0), wall)
        plane("ceiling", 6, (0, 0, 3), wall, rot=(math.pi, 0, 0))
        plane("back", 6, (0, 3, 1.5), wall, rot=(math.pi / 2, 0, 0))
        plane("front", 6, (0, -3, 1.5), wall, rot=(-math.pi / 2, 0, 0))
        plane("right", 6, (3, 0, 1.5), wall, rot=(0, -math.pi / 2, 0))
        wall_with_hole(sc, "slit_wall", wall, -0.05, 0.05, 0.75, 2.25)
        cube("room_fog", 1.0, (0.0, 0.0, 1.5), volume_material("room_fog", ("scatter", (1.0, 1.0, 1.0), 0.2, 0.3)),
             scale=(2.95, 2.95, 1.45))
        light(sc, "lamp", "POINT", (-4.5, 0.0, 1.5), 2000.0, (1.0, 0.9, 0.8))
        camera(sc, (2.6, -2.6, 1.4), (-1.5, 0.8, 1.2), lens=20.0)
    elif name == "area_fog":
        # Principled Volume world fog, a rectangle and a disc area light.
        world_volume(sc, ("principled", (0.9, 0.9, 0.9), 0.08, (0.5, 0.6, 0.8), 0.2))
        plane("floor", 20, (0, 0, 0), grey)
        sphere("ball", 0.6, (0.4, 0.3, 0.6), material("blue", "diffuse", color=(0.2, 0.3, 0.7)))
        # (Both lights out of the frame: Cycles 3.4 leaves area lights out of camera rays.)
        light(sc, "panel", "AREA", (-0.6, 0.0, 3.8), 350.0, (1.0, 0.9, 0.8), shape="RECTANGLE", size=1.0, size_y=0.5)
        light(sc, "disc", "AREA", (3.2, -0.5, 1.5), 150.0, (0.6, 0.8, 1.0), rot=(0, math.radians(60), 0),
              shape="DISK", size=0.6)
        camera(sc, (0, -6, 1.6), (0, 0, 1.0))
    elif name == "area_visible":
        # Fog that scatters backwards (g = -0.2) under an area light in the frame, seen from
        # below and in front: Cycles 3.4 leaves the light itself out of camera rays.
        world_volume(sc, ("principled", (0.9, 0.9, 0.9), 0.1, (0.0, 0.0, 0.0), -0.2))
        plane("floor", 20, (0, 0, 0), grey)
        light(sc, "panel", "AREA", (0.0, 0.5, 2.6), 300.0, shape="RECTANGLE", size=1.2, size_y=0.6)
        camera(sc, (0, -5, 1.2), (0, 0, 1.8))
    elif name == "glass_fog":
        # A glass sphere in world fog, lit by a square area light (caustics through the glass).
        world_volume(sc, ("scatter", (1.0, 1.0, 1.0), 0.1, 0.0))
        plane("floor", 20, (0, 0, 0), grey)
        sphere("glass", 0.7, (0, 0, 0.7), material("glass", "glass", ior=1.45))
        light(sc, "panel", "AREA", (-1.0, 0.5, 3.0), 400.0, rot=(0, math.radians(-15), 0), shape="SQUARE", size=1.0)
        camera(sc, (0, -5, 1.5), (0, 0, 0.7))
    elif name == "glow_box":
        # A glowing Principled Volume cube (scattering, absorbing, emitting (1, 0.5, 0.2) x 2 per
        # metre) on a floor; no light: all light comes from the cube. (With a world fog glowing
        # through an Emission node as well, docs/blender.md gives the numbers: the means agree,
        # one block at the fixed seeds does not.)
        black_world(sc)
        plane("floor", 20, (0, 0, 0), grey)
        cube("glow", 1.0, (0, 0, 0.8), volume_material(
            "glow", ("principled", (0.8, 0.6, 0.4), 0.8, (0.2, 0.2, 0.2), 0.3, (1.0, 0.5, 0.2), 2.0)))
        camera(sc, (0, -5, 1.6), (0, 0, 0.7))
    elif name == "vdb_volume":
        # A Volume object (tests/data/gradient.vdb: density 1 + 0.35 y over 5.75 x 4.75 x 6.25 m,
        # its grid named "density") scaled by 0.3, with a Principled Volume reading its density
        # grid, under a point light. Cycles ray-marches it: a step of a tenth of a voxel.
        black_world(sc)
        plane("floor", 20, (0, 0, 0), grey)
        volume_object(sc, "gradient_smoke", "gradient.vdb", 0.3, (0.0, 0.0, 2.2),
                      volume_material("smoke", ("principled", (0.8, 0.8, 0.8), 1.5, (0.0, 0.0, 0.0), 0.3)))
        light(sc, "lamp", "POINT", (1.5, -1.5, 3.5), 500.0)
        camera(sc, (0, -7, 2.0), (0, 0, 1.4))
    elif name in ("fire_grid", "fire_smoke"):
        # A fire lighting its own smoke and the floor: a Volume object of
        # tests/data/fire.vdb (grids "density" and "temperature", make_test_scenes.py) scaled by
        # 1.5, a Principled Volume reading both (Blackbody Intensity 1, Temperature 1500 K x the
        # grid: up to 3000 K). Cycles ray-marches it, a tenth of a voxel a step.
        black_world(sc)
        plane("floor", 20, (0, 0, 0), grey)
        m = volume_material("flame", ("principled", (0.5, 0.5, 0.5), 1.0, (0.0, 0.0, 0.0), 0.2))
        p = m.node_tree.nodes["Principled Volume"]
        p.inputs["Blackbody Intensity"].default_value = 1.0
        p.inputs["Temperature"].default_value = 1500.0
        p.inputs["Temperature Attribute"].default_value = "temperature"
        volume_object(sc, "fire", "fire.vdb", 1.5, (0.0, 0.0, 0.0), m)
        # A point light too: the smoke's light from the fire alone is sparse in Cycles (it does
        # not sample volume emission as a light: a pixel of thin smoke is 0 but for a rare
        # scattered ray that finds the flame), too heavy-tailed at 128 spp for the block test.
        if name == "fire_grid":
            light(sc, "lamp", "POINT", (1.2, -1.0, 2.0), 40.0)
        camera(sc, (0, -3.2, 1.2), (0, 0, 0.75))
    elif name == "bad_volume":
        # A volume made of a supported node and an unsupported one (a Transparent BSDF in a volume).
        black_world(sc)
        plane("floor", 20, (0, 0, 0), grey)
        m = bpy.data.materials.new("odd_fog")
        m.use_nodes = True
        nt = m.node_tree
        nt.nodes.clear()
        out = nt.nodes.new("ShaderNodeOutputMaterial")
        add = nt.nodes.new("ShaderNodeAddShader")
        s = nt.nodes.new("ShaderNodeVolumeScatter")
        s.inputs["Density"].default_value = 0.5
        e = nt.nodes.new("ShaderNodeBsdfTransparent")
        e.name = "Odd"
        nt.links.new(s.outputs[0], add.inputs[0])
        nt.links.new(e.outputs[0], add.inputs[1])
        nt.links.new(add.outputs[0], out.inputs["Volume"])
        cube("fogbox", 1.0, (0, 0, 0.5), m)
        light(sc, "lamp", "POINT", (0, 0, 3), 100.0)
        camera(sc, (0, -5, 1.5), (0, 0, 0.5))
    else:
        raise SystemExit("unknown scene " + name)
    return sc


def main():
    out, names, o = parse_args()
    os.makedirs(out, exist_ok=True)
    for name in names:
        build(name, o)
        path = os.path.join(out, name + ".blend")
        bpy.ops.wm.save_as_mainfile(filepath=path, compress=False)
        print("make_scenes: wrote " + path)


main()
