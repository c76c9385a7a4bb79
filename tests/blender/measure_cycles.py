# Measures Cycles' conventions on tiny scenes and prints them as JSON: the numbers the unit
# tests of the conversion formulas (test_conversions.py) check against. The measured values are
# kept in cycles_measurements.json; re-measure with
#
#   blender -b --factory-startup -P tests/blender/measure_cycles.py -- OUT.json
#
# Lights: an orthographic camera looks straight down at a white Lambertian plane (Diffuse BSDF,
# colour 1) lit from 2 m above, max_bounces 0 (direct light only); a pixel's value is E / pi, E
# the irradiance, which is compared with the irradiance the candidate formula predicts at that
# pixel (the ratio is 1 if the formula is Cycles'). Volumes: the camera looks through a 1 m
# slab of medium at an emissive plane (strength 1 for camera rays only, 0 for rays scattered in
# the slab, and not sampled as a light: no scattered light reaches the camera), so a pixel is exp(-sigma_t * 1 m): the measured
# extinction is -ln(pixel). Blackbody: the Blackbody node's colour as the world's background,
# and the Principled Volume's blackbody emission through a 1 m slab of density 0.
import json
import math
import os
import sys

import bpy

N = 16  # pixels per side


def base(samples=16):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    c = sc.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.max_bounces = 0
    c.sample_clamp_direct = 0
    c.sample_clamp_indirect = 0
    c.light_sampling_threshold = 0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.seed = 1
    sc.render.threads_mode = "FIXED"
    sc.render.threads = 1
    sc.render.resolution_x = N
    sc.render.resolution_y = N
    sc.render.resolution_percentage = 100
    sc.view_settings.view_transform = "Standard"
    w = bpy.data.worlds.new("w")
    sc.world = w
    w.use_nodes = True
    w.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    cam = bpy.data.cameras.new("c")
    cam.type = "ORTHO"
    cam.ortho_scale = 2.0
    co = bpy.data.objects.new("c", cam)
    co.location = (0, 0, 5)
    sc.collection.objects.link(co)
    sc.camera = co
    return sc


def render(sc):
    import numpy as np
    path = os.path.join(bpy.app.tempdir, "measure.exr")
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.filepath = path
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(path)
    px = np.array(img.pixels[:], dtype=np.float64).reshape(N, N, 4)[::-1, :, :3]  # top row first
    bpy.data.images.remove(img)
    return px


def shader_material(name, build):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    build(nt, out)
    return m


def white_plane():
    bpy.ops.mesh.primitive_plane_add(size=100)
    def b(nt, out):
        d = nt.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = (1, 1, 1, 1)
        nt.links.new(d.outputs[0], out.inputs["Surface"])
    bpy.context.object.data.materials.append(shader_material("white", b))


def pixel_xy():
    import numpy as np
    xs = (np.arange(N) + 0.5) / N * 2 - 1
    return np.meshgrid(xs, -xs)


def light_case(kind, **k):
    sc = base()
    white_plane()
    ld = bpy.data.lights.new("L", kind)
    ld.energy = k["power"]
    if kind in ("POINT", "SPOT"):
        ld.shadow_soft_size = 0
    if kind == "SPOT":
        ld.spot_size = k["spot_size"]
        ld.spot_blend = k["spot_blend"]
    if kind == "SUN":
        ld.angle = 0
    if kind == "AREA":
        ld.shape = k["shape"]
        ld.size = k["size"]
        ld.size_y = k.get("size_y", k["size"])
    lo = bpy.data.objects.new("L", ld)
    lo.location = (0, 0, 2.0)
    sc.collection.objects.link(lo)
    return render(sc)[:, :, 0] * math.pi  # irradiance E = pi * pixel


def volume_case(build):
    sc = base(samples=256)  # scattering paths end in the slab: the pixel is a 0/1 estimate of T
    def em(nt, out):
        e = nt.nodes.new("ShaderNodeEmission")
        lp = nt.nodes.new("ShaderNodeLightPath")  # strength 1 for camera rays, 0 for scattered ones
        nt.links.new(lp.outputs["Is Camera Ray"], e.inputs["Strength"])
        nt.links.new(e.outputs[0], out.inputs["Surface"])
    bpy.ops.mesh.primitive_plane_add(size=100, location=(0, 0, -1))
    m = shader_material("emit", em)
    m.cycles.sample_as_light = False
    bpy.context.object.data.materials.append(m)
    bpy.context.object.visible_volume_scatter = False  # light scattered in the slab never reaches it
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0, 0, 0.5), scale=(10, 10, 1))
    vm = shader_material("vol", build)
    vm.cycles.homogeneous_volume = True
    bpy.context.object.data.materials.append(vm)
    px = render(sc)
    return [float(-math.log(px[:, :, c].mean())) for c in range(3)]


def link_volume(kind, **inputs):
    def b(nt, out):
        n = nt.nodes.new(kind)
        for k, v in inputs.items():
            n.inputs[k].default_value = v
        nt.links.new(n.outputs[0], out.inputs["Volume"])
    return b


def blackbody_node(kelvin):
    """The world's background of colour Blackbody(T), strength 1, seen by the camera: the pixel is
    the node's colour (which it clips to >= 0)."""
    sc = base(samples=1)
    nt = sc.world.node_tree
    bb = nt.nodes.new("ShaderNodeBlackbody")
    bb.inputs[0].default_value = kelvin
    nt.links.new(bb.outputs[0], nt.nodes["Background"].inputs["Color"])
    nt.nodes["Background"].inputs["Strength"].default_value = 1.0
    return [float(x) for x in render(sc).reshape(-1, 3).mean(axis=0)]


def blackbody_volume(kelvin, intensity, tint):
    """A 1 m slab of Principled Volume with density 0 and blackbody emission, seen straight
    through: the pixel is e x 1 m (negative where Cycles' colour is out of gamut)."""
    sc = base(samples=4)
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0, 0, 0.5), scale=(10, 10, 1))
    def b(nt, out):
        p = nt.nodes.new("ShaderNodeVolumePrincipled")
        p.inputs["Density"].default_value = 0.0
        p.inputs["Blackbody Intensity"].default_value = intensity
        p.inputs["Temperature"].default_value = kelvin
        p.inputs["Blackbody Tint"].default_value = tuple(tint) + (1,)
        nt.links.new(p.outputs[0], out.inputs["Volume"])
    m = shader_material("bb", b)
    m.cycles.homogeneous_volume = True
    bpy.context.object.data.materials.append(m)
    return [float(x) for x in render(sc).reshape(-1, 3).mean(axis=0)]


def main():
    out = sys.argv[sys.argv.index("--") + 1]
    res = {"blender": bpy.app.version_string, "pixels": N}
    E = light_case("POINT", power=100.0)
    res["point"] = {"power": 100.0, "height": 2.0, "irradiance": E.tolist()}
    E = light_case("SPOT", power=100.0, spot_size=math.radians(120.0), spot_blend=0.0)
    res["spot"] = {"power": 100.0, "height": 2.0, "spot_size": math.radians(120.0), "irradiance": E.tolist()}
    E = light_case("SPOT", power=100.0, spot_size=math.radians(60.0), spot_blend=0.5)
    res["spot_blend"] = {"power": 100.0, "height": 2.0, "spot_size": math.radians(60.0), "spot_blend": 0.5,
                         "irradiance": E.tolist()}
    E = light_case("SUN", power=3.0)
    res["sun"] = {"strength": 3.0, "irradiance": E.tolist()}
    for shape, size, size_y in (("SQUARE", 0.5, 0.5), ("RECTANGLE", 0.8, 0.3), ("DISK", 0.6, 0.6), ("ELLIPSE", 0.8, 0.4)):
        E = light_case("AREA", power=100.0, shape=shape, size=size, size_y=size_y)
        res["area_" + shape.lower()] = {"power": 100.0, "height": 2.0, "shape": shape, "size": size, "size_y": size_y,
                                        "irradiance": E.tolist()}
    vols = []
    for color, dens, absc in (((0.8, 0.5, 0.2), 0.7, (0.0, 0.0, 0.0)), ((0.3, 0.6, 0.9), 1.3, (0.25, 0.5, 0.9)),
                              ((0.0, 0.0, 0.0), 0.5, (0.1, 0.4, 0.8))):
        st = volume_case(link_volume("ShaderNodeVolumePrincipled", **{"Color": color + (1,), "Density": dens,
                                                                       "Absorption Color": absc + (1,)}))
        vols.append({"node": "principled", "color": color, "density": dens, "absorption_color": absc, "extinction": st})
    st = volume_case(link_volume("ShaderNodeVolumeScatter", **{"Color": (0.9, 0.5, 0.1, 1), "Density": 0.8}))
    vols.append({"node": "scatter", "color": (0.9, 0.5, 0.1), "density": 0.8, "extinction": st})
    st = volume_case(link_volume("ShaderNodeVolumeAbsorption", **{"Color": (0.9, 0.5, 0.1, 1), "Density": 0.8}))
    vols.append({"node": "absorption", "color": (0.9, 0.5, 0.1), "density": 0.8, "extinction": st})
    res["volumes"] = vols
    # Emission: a plane of strength 2.5, colour (1, 0.5, 0.25), seen straight on: pixel = radiance.
    sc = base(samples=4)
    bpy.ops.mesh.primitive_plane_add(size=100)
    def em(nt, out):
        e = nt.nodes.new("ShaderNodeEmission")
        e.inputs["Strength"].default_value = 2.5
        e.inputs["Color"].default_value = (1.0, 0.5, 0.25, 1)
        nt.links.new(e.outputs[0], out.inputs["Surface"])
    bpy.context.object.data.materials.append(shader_material("emit", em))
    res["emission"] = {"color": (1.0, 0.5, 0.25), "strength": 2.5,
                       "pixel": [float(x) for x in render(sc).reshape(-1, 3).mean(axis=0)]}
    # Blackbody (tests/test_blackbody.cpp keeps these numbers).
    res["blackbody"] = {
        "node": [{"kelvin": T, "pixel": blackbody_node(T)}
                 for T in (800, 900, 1000, 1200, 1500, 2000, 2500, 3000, 4000, 5000, 6500, 8000, 10000, 12000, 15000)],
        "volume": [{"kelvin": T, "intensity": b, "tint": t, "pixel": blackbody_volume(T, b, t)}
                   for T, b, t in ((1000, 1.0, (1, 1, 1)), (1500, 1.0, (1, 1, 1)), (2500, 1.0, (1, 1, 1)),
                                   (4000, 1.0, (1, 1, 1)), (1500, 0.5, (1, 1, 1)), (2500, 0.25, (1, 0.5, 0.25)))],
    }
    with open(out, "w") as f:
        json.dump(res, f)
    print("measure_cycles: wrote " + out)


main()
