# brume exporter for Blender: writes a Cycles scene as a brume scene (glTF 2.0 + BRUME_media).
#
# Headless:   blender -b SCENE.blend -P src/blender/brume_export.py -- OUT.gltf
# As add-on:  Edit > Preferences > Add-ons > Install... this file; then File > Export > brume (.gltf)
#
# Meshes, materials, cameras, point/spot/sun lights and transforms come from Blender's own glTF
# exporter (io_scene_gltf2, with its "Unitless" lighting mode: no photometric conversion). This
# file then rewrites what that exporter drops or converts differently from Cycles: media (world
# volume -> the ambient medium, object volumes -> the interior medium of their mesh, Volume
# objects -> density grids), light units as Cycles interprets them, area lights (emissive
# meshes), Diffuse/Glass/Emission shaders, and the render settings (BRUME_render).
#
# Every conversion formula is a plain function below (no bpy), so it can be tested with any
# python3; bpy is imported only when the exporter runs inside Blender. docs/blender.md gives
# the formulas with the Cycles measurements that confirm them.

import base64
import json
import math
import os
import struct
import sys

try:
    import bpy  # inside Blender
except ImportError:  # plain python: the conversion functions only
    bpy = None

bl_info = {
    "name": "brume exporter",
    "description": "Export the scene for the brume fog renderer (glTF 2.0 + BRUME_media)",
    "blender": (3, 4, 0),
    "version": (1, 0, 0),
    "location": "File > Export > brume (.gltf)",
    "category": "Import-Export",
}

PROG = "brume_export"


# --------------------------------------------------------------------------------------------
# Conversion formulas (Cycles' conventions, checked against Cycles 3.4 renders)
# --------------------------------------------------------------------------------------------

def point_intensity(power):
    """Point light of power P [W] -> radiant intensity P/(4 pi) [W/sr]."""
    return power / (4.0 * math.pi)


def spot_intensity(power):
    """Spot light of power P [W] -> on-axis intensity P/(4 pi) [W/sr]: Cycles treats a spot as a
    point light of the same power cut by its cone (and, in Cycles 3.x, times cos(theta) off the
    axis, which brume's glTF spot has not: see spot_cos_factor_error)."""
    return power / (4.0 * math.pi)


def spot_cones(spot_size, spot_blend):
    """Blender spot_size (full cone angle) and spot_blend -> glTF (innerConeAngle, outerConeAngle).

    Cycles: the light is cut at cos(theta) = cos(spot_size/2), and blends with a smoothstep over
    cos(theta) in [cos_o, cos_o + (1 - cos_o) * blend]. brume (glTF) blends with t^2 over
    cos(theta) in [cos_o, cos_i]; so cos_i = cos_o + (1 - cos_o) * blend, the same band in cos
    space (only the shape inside the band differs, smoothstep against t^2). glTF needs
    inner < outer <= pi/2, so the band is at least 1e-4 wide in cos and the outer angle at most
    pi/2."""
    outer = min(0.5 * spot_size, 0.5 * math.pi)
    cos_o = math.cos(outer)
    smooth = (1.0 - cos_o) * max(0.0, min(1.0, spot_blend))
    cos_i = min(1.0, cos_o + max(smooth, 1e-4))
    inner = math.acos(cos_i)
    if not inner < outer:
        inner = max(0.0, outer - 1e-4)
    return inner, outer


def cycles_spot_profile(cos_theta, spot_size, spot_blend):
    """Cycles 3.x spot factor at angle theta from the axis (intensity = P/(4 pi) * this)."""
    cos_half = math.cos(0.5 * spot_size)
    smooth = (1.0 - cos_half) * spot_blend
    if cos_theta <= cos_half:
        return 0.0
    a = cos_theta
    t = cos_theta - cos_half
    if smooth != 0.0 and t < smooth:
        s = t / smooth
        a *= s * s * (3.0 - 2.0 * s)
    return a


def cycles_spot_extras(spot_blend):
    """The light's glTF extras that give brume Cycles' spot profile (cycles_spot_profile, cut at
    outerConeAngle; include/brume/scene/light.h): glTF viewers still read the cones."""
    return {"spotProfile": "cycles", "spotBlend": max(0.0, min(1.0, float(spot_blend)))}


def gltf_spot_profile(cos_theta, inner, outer):
    """brume's spotAttenuation (include/brume/scene/light.h), the glTF formula."""
    cos_i, cos_o = math.cos(inner), math.cos(outer)
    scale = 1.0 / max(0.001, cos_i - cos_o)
    a = min(1.0, max(0.0, cos_theta * scale - cos_o * scale))
    return a * a


def spot_cos_factor_error(spot_size):
    """Largest relative difference inside the cone that Cycles' cos(theta) factor makes: 1 - cos(half angle)."""
    return 1.0 - math.cos(min(0.5 * spot_size, 0.5 * math.pi))


def sun_irradiance(strength):
    """Sun strength [W/m^2] is the irradiance on a surface facing it: glTF directional intensity."""
    return strength


def area_light_area(shape, size, size_y):
    """Area [m^2] of a Blender area light (sizes already scaled by the object)."""
    if shape == "SQUARE":
        return size * size
    if shape == "RECTANGLE":
        return size * size_y
    if shape == "DISK":
        return 0.25 * math.pi * size * size
    if shape == "ELLIPSE":
        return 0.25 * math.pi * size * size_y
    raise ValueError("unknown area light shape " + repr(shape))


def area_radiance(power, area):
    """Area light of power P [W] and area A [m^2] -> radiance P/(4 A) [W/(m^2 sr)] per face.

    Measured in Cycles 3.4 (docs/blender.md): a 0.5 m square light of 100 W gives a radiance of
    100.0 = P/(4A) (to 0.02 %), not P/(pi A); it emits pi P/4 W from its front face."""
    return power / (4.0 * area)


def emission_radiance(color, strength):
    """Emission shader (color C, strength S) on a mesh -> radiance C*S [W/(m^2 sr)]."""
    return [c * strength for c in color]


def emissive_factor_and_strength(radiance):
    """Radiance [r, g, b] -> (glTF emissiveFactor with components <= 1, emissiveStrength)."""
    m = max(radiance)
    if m <= 0:
        return [0.0, 0.0, 0.0], 1.0
    return [c / m for c in radiance], m


def clamp_g(g):
    """Henyey-Greenstein g within brume's |g| < 1 (Cycles clamps to 1 - 1e-3 too)."""
    return max(-0.999, min(0.999, g))


def volume_emission(color, strength):
    """Cycles' volume emission (an Emission node on a Volume output, or the Principled Volume's
    Emission Color x Emission Strength): radiance added per metre, not scaled by the density;
    what brume's medium "emission" is (measured: a slab of thickness d, absorption sigma_a,
    shows e / sigma_a * (1 - exp(-sigma_a d)))."""
    s = max(strength, 0.0)
    return [max(c, 0.0) * s for c in color]


def blackbody(temperature, intensity, tint, attribute=""):
    """Cycles' Principled Volume blackbody (measured against Cycles 3.4: tests/test_blackbody.cpp):
    e = tint * (5.670373e-8 * 1e-6 / pi) * ((1 - b) + b * T^4) * c(T) per metre, c(T) the
    blackbody colour of luminance 1, T = Temperature x the Temperature Attribute's grid where the
    volume has that grid (Volume objects), else Temperature. brume computes e from this object
    (BRUME_media "blackbody"); "attribute" is the exporter's own note of the grid's name."""
    return {"temperature": max(float(temperature), 0.0), "intensity": max(0.0, min(1.0, float(intensity))),
            "tint": [max(float(c), 0.0) for c in tint], "attribute": attribute or ""}


def principled_volume(color, density, absorption_color, anisotropy, emission=(0.0, 0.0, 0.0)):
    """Cycles' Principled Volume (svm_closure.h): sigma_s = color * d, and extinction
    (color + (1 - color)(1 - sqrt(absorption color))) * d, so sigma_a = max(1 - color, 0) *
    max(1 - sqrt(absorption color), 0) * d; d = max(density, 0). emission: volume_emission of
    its emission inputs."""
    d = max(density, 0.0)
    col = [max(c, 0.0) for c in color]
    sig_s = [c * d for c in col]
    sig_a = [max(1.0 - c, 0.0) * max(1.0 - math.sqrt(max(a, 0.0)), 0.0) * d for c, a in zip(col, absorption_color)]
    return {"scattering": sig_s, "absorption": sig_a, "anisotropy": clamp_g(anisotropy), "emission": list(emission)}


def volume_scatter(color, density, anisotropy):
    """Volume Scatter: sigma_s = color * density, no absorption."""
    d = max(density, 0.0)
    return {"scattering": [max(c, 0.0) * d for c in color], "absorption": [0.0, 0.0, 0.0],
            "anisotropy": clamp_g(anisotropy)}


def volume_absorption(color, density):
    """Volume Absorption: Cycles absorbs (1 - color) * density (the colour is what passes)."""
    d = max(density, 0.0)
    return {"scattering": [0.0, 0.0, 0.0], "absorption": [max(1.0 - c, 0.0) * d for c in color], "anisotropy": 0.0}


def _luminance(rgb):
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]


def _emission(m):
    return m.get("emission", [0.0, 0.0, 0.0])


def scale_medium(m, w):
    out = {"scattering": [w * c for c in m["scattering"]], "absorption": [w * c for c in m["absorption"]],
           "anisotropy": m["anisotropy"], "emission": [w * c for c in _emission(m)]}
    if m.get("blackbody"):
        out["blackbody"] = dict(m["blackbody"], tint=[w * c for c in m["blackbody"]["tint"]])
    return out


def add_media(a, b):
    """Add Shader: coefficients add. Cycles then samples a mixture of the two phase functions,
    weighted by their scattering; brume has one g per medium: the scattering-weighted mean.
    Returns (medium, True if the two g differ where both scatter)."""
    sa, sb = _luminance(a["scattering"]), _luminance(b["scattering"])
    if sa + sb > 0:
        g = (a["anisotropy"] * sa + b["anisotropy"] * sb) / (sa + sb)
    else:
        g = 0.0
    differ = sa > 0 and sb > 0 and abs(a["anisotropy"] - b["anisotropy"]) > 1e-6
    out = {"scattering": [x + y for x, y in zip(a["scattering"], b["scattering"])],
           "absorption": [x + y for x, y in zip(a["absorption"], b["absorption"])],
           "anisotropy": clamp_g(g), "emission": [x + y for x, y in zip(_emission(a), _emission(b))]}
    # One blackbody per medium: the first one's (the caller warns when both have one).
    bb = a.get("blackbody") or b.get("blackbody")
    if bb:
        out["blackbody"] = bb
    return out, differ


def mix_media(a, b, fac):
    """Mix Shader with factor f: (1 - f) * a + f * b."""
    f = max(0.0, min(1.0, fac))
    return add_media(scale_medium(a, 1.0 - f), scale_medium(b, f))


def brume_max_depth(max_bounces):
    """Cycles' max_bounces N (N = 0: direct light only) is brume's --max-depth N + 1 (scattering
    events per path, the first one included)."""
    return int(max_bounces) + 1


def render_settings(resolution_x, resolution_y, percentage, samples, max_bounces):
    """The BRUME_render object brume reads as defaults for --res, --spp and --max-depth."""
    return {"width": max(1, int(resolution_x * percentage / 100)),
            "height": max(1, int(resolution_y * percentage / 100)),
            "spp": int(samples), "maxDepth": brume_max_depth(max_bounces)}


def blender_to_gltf(p):
    """A point or direction from Blender's +Z-up frame to glTF's +Y-up frame: (x, z, -y)."""
    return [p[0], p[2], -p[1]]


def area_light_outline(shape, size, size_y, segments=64):
    """The light's outline in its local XY plane (counter-clockwise seen from +Z). Round lights
    become polygons scaled so that their area is the ellipse's, so power matches exactly."""
    if shape in ("SQUARE", "DISK"):
        size_y = size
    hx, hy = 0.5 * size, 0.5 * size_y
    if shape in ("SQUARE", "RECTANGLE"):
        return [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)]
    k = math.sqrt((2.0 * math.pi / segments) / math.sin(2.0 * math.pi / segments))  # polygon area = ellipse area
    return [(k * hx * math.cos(2 * math.pi * i / segments), k * hy * math.sin(2 * math.pi * i / segments))
            for i in range(segments)]


def polygon_area(pts):
    return 0.5 * abs(sum(pts[i][0] * pts[(i + 1) % len(pts)][1] - pts[(i + 1) % len(pts)][0] * pts[i][1]
                         for i in range(len(pts))))


# --------------------------------------------------------------------------------------------
# Messages
# --------------------------------------------------------------------------------------------

class ExportError(Exception):
    pass


class Report:
    def __init__(self):
        self.warnings = []

    def warn(self, text):
        line = "%s: warning: %s" % (PROG, " ".join(str(text).split()))
        self.warnings.append(line)
        print(line, file=sys.stderr, flush=True)


# --------------------------------------------------------------------------------------------
# glTF JSON helpers (no bpy)
# --------------------------------------------------------------------------------------------

def add_buffer_mesh(gltf, name, positions, normals, indices, material):
    """Appends a mesh with one triangle primitive whose data sit in a new data: URI buffer."""
    pos = b"".join(struct.pack("<3f", *p) for p in positions)
    nor = b"".join(struct.pack("<3f", *n) for n in normals)
    idx = b"".join(struct.pack("<I", i) for i in indices)
    data = pos + nor + idx
    buffers = gltf.setdefault("buffers", [])
    buffers.append({"byteLength": len(data),
                    "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode("ascii")})
    b = len(buffers) - 1
    views = gltf.setdefault("bufferViews", [])
    accessors = gltf.setdefault("accessors", [])
    first_view = len(views)
    views.append({"buffer": b, "byteOffset": 0, "byteLength": len(pos)})
    views.append({"buffer": b, "byteOffset": len(pos), "byteLength": len(nor)})
    views.append({"buffer": b, "byteOffset": len(pos) + len(nor), "byteLength": len(idx)})
    lo = [min(p[k] for p in positions) for k in range(3)]
    hi = [max(p[k] for p in positions) for k in range(3)]
    a0 = len(accessors)
    accessors.append({"bufferView": first_view, "componentType": 5126, "count": len(positions), "type": "VEC3",
                      "min": lo, "max": hi})
    accessors.append({"bufferView": first_view + 1, "componentType": 5126, "count": len(normals), "type": "VEC3"})
    accessors.append({"bufferView": first_view + 2, "componentType": 5125, "count": len(indices), "type": "SCALAR"})
    prim = {"attributes": {"POSITION": a0, "NORMAL": a0 + 1}, "indices": a0 + 2, "mode": 4}
    if material is not None:
        prim["material"] = material
    meshes = gltf.setdefault("meshes", [])
    meshes.append({"name": name, "primitives": [prim]})
    return len(meshes) - 1


def add_root_node(gltf, node):
    nodes = gltf.setdefault("nodes", [])
    nodes.append(node)
    scene = gltf.get("scene", 0)
    scenes = gltf.setdefault("scenes", [{"nodes": []}])
    scenes[scene].setdefault("nodes", []).append(len(nodes) - 1)
    return len(nodes) - 1


def use_extension(gltf, name, required=False):
    used = gltf.setdefault("extensionsUsed", [])
    if name not in used:
        used.append(name)
    if required:
        req = gltf.setdefault("extensionsRequired", [])
        if name not in req:
            req.append(name)


def medium_json(name, m, density=None):
    out = {"name": name}
    for key in ("scattering", "absorption"):
        v = [float(x) for x in m[key]]
        out[key] = v[0] if v[0] == v[1] == v[2] else v
    out["anisotropy"] = float(m["anisotropy"])
    if density:
        out["density"] = density
    e = [float(x) for x in _emission(m)]
    if max(e) > 0:
        out["emission"] = e
    bb = m.get("blackbody")
    if bb and bb["intensity"] > 0 and max(bb["tint"]) > 0:
        out["blackbody"] = bb.get("grid_ref") or {"temperature": bb["temperature"]}
        out["blackbody"] = dict(out["blackbody"], intensity=bb["intensity"], tint=list(bb["tint"]))
    return out


# --------------------------------------------------------------------------------------------
# Reading Blender's shader nodes (bpy)
# --------------------------------------------------------------------------------------------

def _rgb(v):
    return [float(v[0]), float(v[1]), float(v[2])]


def _input_value(node, name, owner, report, what):
    """An input's own value; a linked input (a texture, an attribute...) is reported and its
    unlinked default used."""
    sock = node.inputs.get(name)
    if sock is None:
        return None
    if sock.is_linked:
        src = sock.links[0].from_node
        report.warn("%s: node '%s' input '%s' is driven by node '%s' (%s): not exported, using its value %s"
                    % (owner, node.name, name, src.name, what, _fmt_value(sock.default_value)))
    v = sock.default_value
    try:
        return [float(x) for x in v][:3]
    except TypeError:
        return float(v)


def _fmt_value(v):
    try:
        return "(" + ", ".join("%.4g" % x for x in list(v)[:3]) + ")"
    except TypeError:
        return "%.4g" % v


def _active_output(tree, idname):
    outs = [n for n in tree.nodes if n.bl_idname == idname]
    for n in outs:
        if getattr(n, "is_active_output", False) and getattr(n, "target", "ALL") in ("ALL", "CYCLES"):
            return n
    for n in outs:
        if getattr(n, "target", "ALL") in ("ALL", "CYCLES"):
            return n
    return outs[0] if outs else None


def _follow(sock):
    """The node feeding a socket, through reroutes; None if unlinked."""
    while sock is not None and sock.is_linked:
        node = sock.links[0].from_node
        if node.bl_idname == "NodeReroute":
            sock = node.inputs[0]
            continue
        return node
    return None


ZERO_MEDIUM = {"scattering": [0.0, 0.0, 0.0], "absorption": [0.0, 0.0, 0.0], "anisotropy": 0.0}


def _warn_two_blackbodies(a, b, owner, node, report):
    if a.get("blackbody") and b.get("blackbody"):
        report.warn("%s: node '%s' combines two blackbody emissions: brume's medium has one; the first is exported"
                    % (owner, node.name))


def medium_from_node(node, owner, report, depth=0):
    """The medium a volume shader node describes: (medium, unsupported node names)."""
    if node is None or depth > 64:
        return dict(ZERO_MEDIUM), []
    t = node.bl_idname
    if t == "ShaderNodeVolumePrincipled":
        color = _input_value(node, "Color", owner, report, "textures driving volumes are not exported")
        density = _input_value(node, "Density", owner, report, "textures driving volumes are not exported")
        absorption = _input_value(node, "Absorption Color", owner, report, "textures driving volumes are not exported")
        g = _input_value(node, "Anisotropy", owner, report, "textures driving volumes are not exported")
        emission = [0.0, 0.0, 0.0]
        s = node.inputs.get("Emission Strength")
        if s is not None and (s.is_linked or s.default_value > 0):
            strength = _input_value(node, "Emission Strength", owner, report, "textures driving volumes are not exported")
            ecol = _input_value(node, "Emission Color", owner, report, "textures driving volumes are not exported")
            emission = volume_emission(ecol, strength)
        m = principled_volume(color, density, absorption, g, emission)
        s = node.inputs.get("Blackbody Intensity")
        if s is not None and (s.is_linked or s.default_value > 0):
            b = _input_value(node, "Blackbody Intensity", owner, report, "textures driving volumes are not exported")
            t = _input_value(node, "Temperature", owner, report, "textures driving volumes are not exported")
            tint = _input_value(node, "Blackbody Tint", owner, report, "textures driving volumes are not exported")
            attr = node.inputs.get("Temperature Attribute")
            m["blackbody"] = blackbody(t, b, tint if tint is not None else (1.0, 1.0, 1.0),
                                       getattr(attr, "default_value", "") if attr is not None else "")
        return m, []
    if t == "ShaderNodeEmission":
        color = _input_value(node, "Color", owner, report, "textures driving volumes are not exported")
        strength = _input_value(node, "Strength", owner, report, "textures driving volumes are not exported")
        return dict(ZERO_MEDIUM, emission=volume_emission(color, strength)), []
    if t == "ShaderNodeVolumeScatter":
        color = _input_value(node, "Color", owner, report, "textures driving volumes are not exported")
        density = _input_value(node, "Density", owner, report, "textures driving volumes are not exported")
        g = _input_value(node, "Anisotropy", owner, report, "textures driving volumes are not exported")
        return volume_scatter(color, density, g), []
    if t == "ShaderNodeVolumeAbsorption":
        color = _input_value(node, "Color", owner, report, "textures driving volumes are not exported")
        density = _input_value(node, "Density", owner, report, "textures driving volumes are not exported")
        return volume_absorption(color, density), []
    if t == "ShaderNodeAddShader":
        a, ua = medium_from_node(_follow(node.inputs[0]), owner, report, depth + 1)
        b, ub = medium_from_node(_follow(node.inputs[1]), owner, report, depth + 1)
        m, differ = add_media(a, b)
        _warn_two_blackbodies(a, b, owner, node, report)
        if differ:
            report.warn("%s: node '%s' adds phase functions of different anisotropy (%.3g, %.3g): brume uses their "
                        "scattering-weighted mean %.3g" % (owner, node.name, a["anisotropy"], b["anisotropy"],
                                                         m["anisotropy"]))
        return m, ua + ub
    if t == "ShaderNodeMixShader":
        fac = _input_value(node, "Fac", owner, report, "textures driving volumes are not exported")
        a, ua = medium_from_node(_follow(node.inputs[1]), owner, report, depth + 1)
        b, ub = medium_from_node(_follow(node.inputs[2]), owner, report, depth + 1)
        m, differ = mix_media(a, b, fac)
        _warn_two_blackbodies(a, b, owner, node, report)
        if differ:
            report.warn("%s: node '%s' mixes phase functions of different anisotropy: brume uses their "
                        "scattering-weighted mean %.3g" % (owner, node.name, m["anisotropy"]))
        return m, ua + ub
    report.warn("%s: volume node '%s' (%s) cannot be exported to brume: it adds nothing to the medium"
                % (owner, node.name, t))
    return dict(ZERO_MEDIUM), [node.name]


def density_grid_of_node(node, depth=0):
    """The grid a volume shader node reads as its density on a Volume object, as Cycles reads it:
    a Principled Volume's 'Density Attribute' (by default "density"); for other volume nodes, the
    attribute named by an Attribute node (or a Volume Info node's Density output) driving their
    Density input; through Add and Mix shaders, the first one found. None if none reads a grid."""
    if node is None or depth > 64:
        return None
    t = node.bl_idname
    if t == "ShaderNodeVolumePrincipled":
        sock = node.inputs.get("Density Attribute")
        name = getattr(sock, "default_value", "") if sock is not None else ""
        return name or "density"
    if t in ("ShaderNodeVolumeScatter", "ShaderNodeVolumeAbsorption"):
        src = _follow(node.inputs.get("Density"))
        if src is None:
            return None
        if src.bl_idname == "ShaderNodeAttribute":
            return getattr(src, "attribute_name", "") or None
        if src.bl_idname == "ShaderNodeVolumeInfo":
            return "density"
        return None
    if t in ("ShaderNodeAddShader", "ShaderNodeMixShader"):
        first = 0 if t == "ShaderNodeAddShader" else 1
        for sock in node.inputs[first:first + 2]:
            name = density_grid_of_node(_follow(sock), depth + 1)
            if name:
                return name
    return None


def volume_of_tree(tree, output_idname, owner, report):
    """(medium or None, unsupported nodes) for a material's or world's Volume output."""
    if tree is None:
        return None, []
    out = _active_output(tree, output_idname)
    if out is None:
        return None, []
    node = _follow(out.inputs.get("Volume"))
    if node is None:
        return None, []
    return medium_from_node(node, owner, report)


def surface_node(tree):
    if tree is None:
        return None
    out = _active_output(tree, "ShaderNodeOutputMaterial")
    return _follow(out.inputs.get("Surface")) if out is not None else None


def material_json(mat, gm, report):
    """Rewrites glTF material gm after Blender material mat as Cycles renders it, within brume's
    Diffuse / Glossy / Dielectric kinds. Returns False if the surface is unlinked (no material)."""
    owner = "material '%s'" % mat.name
    if not mat.use_nodes:
        c = _rgb(mat.diffuse_color)
        gm["pbrMetallicRoughness"] = {"baseColorFactor": c + [1.0], "metallicFactor": float(mat.metallic),
                                      "roughnessFactor": float(mat.roughness)}
        return True
    node = surface_node(mat.node_tree)
    if node is None:
        return False
    t = node.bl_idname
    pbr = gm.setdefault("pbrMetallicRoughness", {})
    ext = gm.setdefault("extensions", {})
    for k in ("KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_emissive_strength"):
        ext.pop(k, None)
    gm.pop("emissiveFactor", None)

    def emission(radiance):
        f, s = emissive_factor_and_strength(radiance)
        if max(radiance) > 0:
            gm["emissiveFactor"] = f
            if s != 1.0:
                ext["KHR_materials_emissive_strength"] = {"emissiveStrength": s}

    what = "textures on surfaces other than glTF's base colour are not exported"
    if t == "ShaderNodeBsdfDiffuse":
        c = _input_value(node, "Color", owner, report, "base colour textures: use a Principled BSDF")
        r = _input_value(node, "Roughness", owner, report, what)
        if r > 0:
            report.warn("%s: node '%s': Oren-Nayar roughness %.3g is drawn as Lambert" % (owner, node.name, r))
        pbr.clear()
        pbr.update({"baseColorFactor": c + [1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0})
    elif t == "ShaderNodeBsdfGlass":
        c = _input_value(node, "Color", owner, report, what)
        r = _input_value(node, "Roughness", owner, report, what)
        ior = _input_value(node, "IOR", owner, report, what)
        if r > 0:
            report.warn("%s: node '%s': glass roughness %.3g is drawn as smooth glass" % (owner, node.name, r))
        if min(c) < 1:
            report.warn("%s: node '%s': glass colour %s is not exported (brume's glass is clear)"
                        % (owner, node.name, _fmt_value(c)))
        pbr.clear()
        pbr.update({"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.0})
        ext["KHR_materials_transmission"] = {"transmissionFactor": 1.0}
        ext["KHR_materials_ior"] = {"ior": float(ior)}
    elif t == "ShaderNodeEmission":
        c = _input_value(node, "Color", owner, report, what)
        s = _input_value(node, "Strength", owner, report, what)
        pbr.clear()
        pbr.update({"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0})
        emission(emission_radiance(c, s))
    elif t == "ShaderNodeBsdfPrincipled":
        # glTF's own exporter wrote base colour (and its texture), metallic and roughness.
        metallic = _input_value(node, "Metallic", owner, report, what)
        trans = _input_value(node, "Transmission", owner, report, what)
        spec = _input_value(node, "Specular", owner, report, what)
        ior = _input_value(node, "IOR", owner, report, what)
        if not node.inputs["Base Color"].is_linked:
            pbr["baseColorFactor"] = _rgb(node.inputs["Base Color"].default_value) + [1.0]
        pbr["metallicFactor"] = float(metallic)
        pbr["roughnessFactor"] = float(_input_value(node, "Roughness", owner, report, what))
        if trans >= 0.5:
            ext["KHR_materials_transmission"] = {"transmissionFactor": float(trans)}
            ext["KHR_materials_ior"] = {"ior": float(ior)}
            if trans < 1:
                report.warn("%s: node '%s': transmission %.3g is drawn as clear glass" % (owner, node.name, trans))
        elif trans > 0:
            report.warn("%s: node '%s': transmission %.3g < 0.5 is dropped" % (owner, node.name, trans))
        if metallic < 1 and spec > 0 and trans < 0.5:
            report.warn("%s: node '%s': the specular layer (Specular %.3g) is not drawn: brume's material is "
                        "(1 - metallic) Lambert + metallic GGX" % (owner, node.name, spec))
        for name in ("Subsurface", "Sheen", "Clearcoat"):
            s = node.inputs.get(name)
            if s is not None and (s.is_linked or s.default_value > 0):
                report.warn("%s: node '%s': '%s' is not exported" % (owner, node.name, name))
        ec = _input_value(node, "Emission", owner, report, what)
        es = _input_value(node, "Emission Strength", owner, report, what)
        if ec is not None and es is not None:
            emission(emission_radiance(ec, es))
    else:
        report.warn("%s: surface node '%s' (%s) is not mapped: kept as Blender's glTF exporter wrote it"
                    % (owner, node.name, t))
    if not ext:
        gm.pop("extensions", None)
    for k in ("KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_emissive_strength"):
        if k in ext:
            use_extension_later.add(k)
    return True


use_extension_later = set()


# --------------------------------------------------------------------------------------------
# The export (bpy)
# --------------------------------------------------------------------------------------------

def volume_density_scale(matrix3, space):
    """Cycles' density (and emission) factor for a Volume object (Blender's
    BKE_volume_density_scale): 1/|M (1, 1, 1)/sqrt(3)| in render space "OBJECT" (the default), M
    the object's 3x3 world matrix (rows); 1 in "WORLD". Measured: a Volume object scaled by 0.5
    glows twice as much per metre."""
    if space != "OBJECT":
        return 1.0
    u = 1.0 / math.sqrt(3.0)
    v = [sum(row[k] * u for k in range(3)) for row in matrix3]
    n = math.sqrt(sum(c * c for c in v))
    return 1.0 / n if n > 0 else 1.0


def _volume_grids(vol):
    """A Volume's grids by name: their 4x4 index-to-object matrices (rows); none if the file
    cannot be read (the callers warn or go without)."""
    try:
        vol.grids.load()
        return {g.name: [list(r) for r in g.matrix_object] for g in vol.grids}
    except Exception:  # noqa: BLE001
        return {}


def _volume_blackbody_grid(vol, m, uri, obj, report):
    """A Volume object's blackbody reads its Temperature Attribute's grid if the file has one:
    T = Temperature x grid (then brume's "blackbody" is that grid, scaled). Returns its name."""
    bb = m.get("blackbody")
    if not bb or not bb["attribute"]:
        return None
    if bb["attribute"] not in _volume_grids(vol):
        report.warn("volume object '%s': no grid '%s' for the blackbody's temperature: %g K everywhere"
                    % (obj.name, bb["attribute"], bb["temperature"]))
        return None
    bb["grid_ref"] = {"uri": uri, "grid": bb["attribute"], "scale": bb["temperature"]}
    return bb["attribute"]


def _world_matrix_gltf(obj, offset=(0.0, 0.0, 0.0)):
    """Object's world matrix in glTF's frame, as a column-major list of 16; offset: a translation
    in the object's own space applied first."""
    import mathutils
    conv = mathutils.Matrix(((1, 0, 0, 0), (0, 0, 1, 0), (0, -1, 0, 0), (0, 0, 0, 1)))
    m = conv @ obj.matrix_world @ mathutils.Matrix.Translation(offset)
    return [m[r][c] for c in range(4) for r in range(4)]


def half_voxel_offset(grid_matrix):
    """Cycles 3.4 reads voxel (i, j, k) of a Volume object's grid at index (i, j, k) + 1/2, where
    OpenVDB (and brume) put it at (i, j, k): the grid's linear part times (1/2, 1/2, 1/2), in
    object space (grid_matrix: the grid's 4x4 index-to-object matrix, rows). Measured on the
    vdb_volume round trip: without it brume's cloud sat half a voxel low and to the left."""
    return tuple(0.5 * (grid_matrix[r][0] + grid_matrix[r][1] + grid_matrix[r][2]) for r in range(3))


def _object_of_node(node):
    name = node.get("name")
    return bpy.data.objects.get(name) if name else None


def _volume_material_of(obj):
    for slot in obj.material_slots:
        if slot.material is not None and slot.material.use_nodes:
            out = _active_output(slot.material.node_tree, "ShaderNodeOutputMaterial")
            if out is not None and _follow(out.inputs.get("Volume")) is not None:
                return slot.material
    return None


def export_scene(filepath, context=None, report=None):
    """Exports the current scene to filepath (.gltf). Returns the Report; raises ExportError."""
    report = report or Report()
    context = context or bpy.context
    scene = context.scene
    filepath = os.path.abspath(filepath)
    if not filepath.lower().endswith(".gltf"):
        raise ExportError("%s: the output must be a .gltf file" % filepath)
    outdir = os.path.dirname(filepath)
    if not os.path.isdir(outdir):
        raise ExportError("%s: output directory does not exist" % outdir)
    if not os.access(outdir, os.W_OK):
        raise ExportError("%s: output directory is not writable" % outdir)
    if scene.camera is None:
        raise ExportError("the scene has no active camera")
    if scene.camera.data.type != "PERSP":
        raise ExportError("camera '%s' is not perspective (brume renders perspective cameras only)" % scene.camera.name)
    if scene.render.engine != "CYCLES":
        report.warn("render engine is %s: the export follows Cycles' conventions" % scene.render.engine)

    use_extension_later.clear()
    # Blender's glTF exporter: "Unitless" (COMPAT) lighting, i.e. W -> W/sr by P/(4 pi), sun in
    # W/m^2, no 683 lm/W. brume's own values overwrite its lights below in any case.
    result = bpy.ops.export_scene.gltf(
        filepath=filepath, export_format="GLTF_SEPARATE", export_cameras=True, export_lights=True,
        export_extras=False, export_yup=True, export_apply=True, use_selection=False,
        convert_lighting_mode="COMPAT", export_animations=False)
    if "FINISHED" not in result:
        raise ExportError("Blender's glTF exporter failed: %s" % (result,))
    with open(filepath, encoding="utf-8") as f:
        gltf = json.load(f)

    nodes = gltf.get("nodes", [])
    cycles = scene.cycles

    # --- Materials -----------------------------------------------------------------------
    gltf_materials = gltf.get("materials", [])
    surfaceless = set()
    for i, gm in enumerate(gltf_materials):
        mat = bpy.data.materials.get(gm.get("name", ""))
        if mat is None:
            continue
        if not material_json(mat, gm, report):
            surfaceless.add(i)

    # --- Media -------------------------------------------------------------------------------
    media = []
    medium_of_material = {}

    def add_medium(name, m, density=None):
        media.append(medium_json(name, m, density))
        return len(media) - 1

    ambient = None
    world_medium = None
    world = scene.world
    if world is not None and world.use_nodes:
        m, bad = volume_of_tree(world.node_tree, "ShaderNodeOutputWorld", "world '%s'" % world.name, report)
        if m is not None:
            ambient = add_medium(world.name, m)
            world_medium = m
        bg = _active_output(world.node_tree, "ShaderNodeOutputWorld")
        sn = _follow(bg.inputs.get("Surface")) if bg is not None else None
        if sn is not None:
            lit = True
            if sn.bl_idname == "ShaderNodeBackground" and not sn.inputs["Color"].is_linked:
                col = sn.inputs["Color"].default_value
                lit = sn.inputs["Strength"].default_value * max(col[0], col[1], col[2]) > 0
            if lit:
                report.warn("world '%s': node '%s': background light is not exported (brume has no environment "
                            "light: rays that leave the scene are black)" % (world.name, sn.name))
    elif world is not None and max(world.color) > 0:
        report.warn("world '%s': background colour is not exported (rays that leave the scene are black)" % world.name)

    # Object volumes: the interior medium of each glTF mesh whose object has a volume material.
    mesh_medium = {}
    for node in nodes:
        if "mesh" not in node:
            continue
        obj = _object_of_node(node)
        if obj is None:
            continue
        mat = _volume_material_of(obj)
        if mat is None:
            continue
        if mat.name not in medium_of_material:
            m, bad = volume_of_tree(mat.node_tree, "ShaderNodeOutputMaterial", "material '%s'" % mat.name, report)
            if bad:
                report.warn("object '%s': material '%s': the medium is exported without node(s) %s"
                            % (obj.name, mat.name, ", ".join("'%s'" % b for b in bad)))
            if world_medium is not None:
                # Cycles stacks volumes: inside an object the world's volume is evaluated too,
                # and their closures add; brume's interior medium replaces the ambient one.
                m, differ = add_media(m, world_medium)
                if differ:
                    report.warn("material '%s': inside it Cycles adds the world's volume, of another anisotropy: "
                                "brume uses their scattering-weighted mean %.3g" % (mat.name, m["anisotropy"]))
            medium_of_material[mat.name] = add_medium(mat.name, m)
        mi = medium_of_material[mat.name]
        prev = mesh_medium.get(node["mesh"])
        if prev is not None and prev != mi:
            report.warn("object '%s': mesh '%s' is shared with another object of another volume material: "
                        "it keeps the first one's medium" % (obj.name, obj.data.name))
            continue
        mesh_medium[node["mesh"]] = mi
        slots = [s.material for s in obj.material_slots if s.material is not None]
        if len({id(s) for s in slots}) > 1:
            report.warn("object '%s': several materials; the whole mesh bounds material '%s''s medium"
                        % (obj.name, mat.name))
    for mesh_index, mi in mesh_medium.items():
        gmesh = gltf["meshes"][mesh_index]
        gmesh.setdefault("extensions", {})["BRUME_media"] = {"interior": mi}
        for prim in gmesh.get("primitives", []):
            if prim.get("material") in surfaceless:
                del prim["material"]  # a pure medium boundary: invisible
    # Meshes with a surfaceless material and no volume: nothing to draw.
    for gmesh in gltf.get("meshes", []):
        for prim in gmesh.get("primitives", []):
            if prim.get("material") in surfaceless:
                report.warn("mesh '%s': material '%s' has no surface and no volume: drawn grey"
                            % (gmesh.get("name", "?"), gltf_materials[prim["material"]].get("name", "?")))
                del prim["material"]

    # Volume objects (OpenVDB): a box around the grid bounds a medium with a density grid.
    for obj in scene.objects:
        if obj.type != "VOLUME" or not obj.visible_get():
            continue
        vol = obj.data
        mat = _volume_material_of(obj)
        if mat is None:
            report.warn("volume object '%s' has no volume material: not exported" % obj.name)
            continue
        m, bad = volume_of_tree(mat.node_tree, "ShaderNodeOutputMaterial", "material '%s'" % mat.name, report)
        path = bpy.path.abspath(vol.filepath)
        if vol.is_sequence or not path or not os.path.isfile(path):
            report.warn("volume object '%s': no single .vdb file on disk ('%s'): not exported" % (obj.name, vol.filepath))
            continue
        try:
            uri = os.path.relpath(path, outdir)
        except ValueError:
            uri = path
        # The grid the material reads (Principled Volume's Density Attribute, or an Attribute
        # node): its name in the .vdb. A material that reads none gets "density" (warned).
        out = _active_output(mat.node_tree, "ShaderNodeOutputMaterial")
        grid = density_grid_of_node(_follow(out.inputs.get("Volume")) if out is not None else None)
        if grid is None:
            grid = "density"
            report.warn("volume object '%s': material '%s' reads no grid as its density: grid 'density' used"
                        % (obj.name, mat.name))
        if world_medium is not None:
            report.warn("volume object '%s': Cycles adds the world's volume inside it too; brume's medium there is "
                        "the grid's alone" % obj.name)
        bb_grid = _volume_blackbody_grid(vol, m, uri, obj, report)
        if max(_emission(m)) > 0 and bb_grid:
            report.warn("volume object '%s': its emission is not exported: brume's medium takes a blackbody "
                        "temperature grid or emission, not both" % obj.name)
            m["emission"] = [0.0, 0.0, 0.0]
        if max(_emission(m)) > 0:
            report.warn("volume object '%s': its emission is exported the same everywhere in its box, not "
                        "following a grid" % obj.name)
        # Cycles' render space "Object" (the default): densities and emission per unit of the
        # object's space, scaled by 1/|M (1, 1, 1)/sqrt(3)|, M the object's world matrix.
        space = getattr(getattr(vol, "render", None), "space", "OBJECT")
        ds = volume_density_scale([list(r)[:3] for r in obj.matrix_world[:3]], space)
        if ds != 1.0:
            m = scale_medium(m, ds)
        mi = add_medium(mat.name + "@" + obj.name, m, {"uri": uri, "grid": grid, "scale": 1.0})
        # The grid moved by Cycles' half voxel (half_voxel_offset); the box around the grid's
        # bounds grown by two voxels a side, so that it holds the trilinear fall-off beyond the
        # outermost voxels wherever the half voxel puts them (outside the grid the medium is
        # empty: a larger box changes nothing else).
        gm = _volume_grids(vol).get(grid)
        off = half_voxel_offset(gm) if gm else (0.0, 0.0, 0.0)
        pad = [2.0 * sum(abs(gm[r][c]) for c in range(3)) if gm else 0.0 for r in range(3)]
        bb = [tuple(v) for v in obj.bound_box]
        lo = [min(v[k] for v in bb) - off[k] - pad[k] for k in range(3)]
        hi = [max(v[k] for v in bb) - off[k] + pad[k] for k in range(3)]
        corners = [(lo[0] if i & 1 == 0 else hi[0], lo[1] if i & 2 == 0 else hi[1], lo[2] if i & 4 == 0 else hi[2])
                   for i in range(8)]
        # Outward counter-clockwise faces of the box (corner bits: x=1, y=2, z=4).
        quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
        idx = []
        for a, b, c, d in quads:
            idx += [a, b, c, a, c, d]
        mesh = add_buffer_mesh(gltf, obj.name, corners, [(0.0, 0.0, 1.0)] * 8, idx, None)
        gltf["meshes"][mesh]["extensions"] = {"BRUME_media": {"interior": mi}}
        add_root_node(gltf, {"name": obj.name, "mesh": mesh, "matrix": _world_matrix_gltf(obj, off)})
        report.warn("volume object '%s': grid '%s' of %s, density scale per unit of the grid%s; other grids "
                    "(color, flame) are not exported" % (obj.name, grid, uri,
                                                         ", temperature grid '%s'" % bb_grid if bb_grid else ""))
    # A volume material on an object that is not a mesh or volume (curves, text...) is skipped by
    # glTF: say so.
    exported = {n.get("name") for n in nodes}
    for obj in scene.objects:
        if obj.type in ("MESH", "VOLUME") or not obj.visible_get():
            continue
        if hasattr(obj, "material_slots") and _volume_material_of(obj) is not None and obj.name not in exported:
            report.warn("object '%s' (%s): its volume material is not exported (convert it to a mesh)"
                        % (obj.name, obj.type))

    if media:
        ext = {"media": media}
        if ambient is not None:
            ext["ambient"] = ambient
        gltf.setdefault("extensions", {})["BRUME_media"] = ext
        use_extension(gltf, "BRUME_media", required=True)

    # --- Lights ------------------------------------------------------------------------------
    lights = gltf.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    for gl in lights:
        ld = bpy.data.lights.get(gl.get("name", ""))
        if ld is None:
            continue
        owner = "light '%s'" % ld.name
        if ld.use_nodes:
            report.warn("%s: light nodes are ignored (power and colour only)" % owner)
        gl["color"] = _rgb(ld.color)
        gl.pop("range", None)
        if ld.type == "POINT":
            gl["intensity"] = point_intensity(ld.energy)
        elif ld.type == "SPOT":
            gl["intensity"] = spot_intensity(ld.energy)
            inner, outer = spot_cones(ld.spot_size, ld.spot_blend)
            gl["spot"] = {"innerConeAngle": inner, "outerConeAngle": outer}
            gl.setdefault("extras", {}).update(cycles_spot_extras(ld.spot_blend))
            if ld.spot_size > math.pi:
                report.warn("%s: spot cone %.1f deg is wider than brume's 180 deg: cut at 180 deg"
                            % (owner, math.degrees(ld.spot_size)))
        elif ld.type == "SUN":
            gl["intensity"] = sun_irradiance(ld.energy)
            if ld.angle > 0:
                report.warn("%s: sun angle %.3g deg is drawn as a parallel light (angle 0)"
                            % (owner, math.degrees(ld.angle)))
        radius = getattr(ld, "shadow_soft_size", 0.0)
        if ld.type in ("POINT", "SPOT") and radius > 0:
            if ld.type == "POINT":
                gl["extras"] = {"radius": float(radius)}
                report.warn("%s: radius %.3g m: brume draws a sphere light of the same power; Cycles draws a disc "
                            "facing the shaded point (the same intensity from afar, different within a few radii)"
                            % (owner, radius))
            else:
                report.warn("%s: radius %.3g m is drawn as a point (brume's spot lights have no size)" % (owner, radius))
    # Blender's glTF exporter scales nothing in light nodes, but a light object's scale does not
    # scale its radius in Cycles either.

    # Area lights: transparent emissive meshes of the same shape, unseen by the camera, radiance
    # P / (4 A) on the front face (-Z).
    for obj in scene.objects:
        if obj.type != "LIGHT" or obj.data.type != "AREA" or not obj.visible_get():
            continue
        ld = obj.data
        owner = "light '%s'" % ld.name
        if ld.use_nodes:
            report.warn("%s: light nodes are ignored (power and colour only)" % owner)
        if getattr(ld, "spread", math.pi) < math.pi - 1e-6:
            report.warn("%s: spread %.1f deg is drawn as 180 deg (Lambertian)" % (owner, math.degrees(ld.spread)))
        outline = area_light_outline(ld.shape, ld.size, ld.size_y)
        mw = obj.matrix_world
        world_pts = [mw @ _vec3(x, y, 0.0) for x, y in outline]
        normal = (mw.to_3x3().inverted_safe().transposed() @ _vec3(0.0, 0.0, -1.0)).normalized()
        # The light's world area (the object's scale and shear stretch it as in Cycles).
        area = _world_polygon_area(world_pts)
        if area <= 0:
            report.warn("%s: zero area: not exported" % owner)
            continue
        L = area_radiance(ld.energy, area)
        radiance = [L * c for c in ld.color]
        factor, strength = emissive_factor_and_strength(radiance)
        # As Cycles 3.4 renders its lights: rays cross them (no shadow, nothing hidden behind),
        # and camera rays do not see an area light (measured: docs/blender.md).
        gm = {"name": "brume area light " + ld.name, "emissiveFactor": factor,
              "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0,
                                       "roughnessFactor": 1.0},
              "extras": {"transparent": True, "cameraVisible": False}}
        if strength != 1.0:
            gm["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": strength}}
            use_extension_later.add("KHR_materials_emissive_strength")
        gltf.setdefault("materials", []).append(gm)
        positions = [blender_to_gltf(p) for p in world_pts]
        n = blender_to_gltf(normal)
        # Fan triangles, reversed: counter-clockwise seen from -Z (the emitting side).
        idx = []
        for i in range(1, len(positions) - 1):
            idx += [0, i + 1, i]
        mesh = add_buffer_mesh(gltf, "area light " + ld.name, positions, [n] * len(positions), idx,
                               len(gltf["materials"]) - 1)
        add_root_node(gltf, {"name": obj.name, "mesh": mesh})
    for k in sorted(use_extension_later):
        use_extension(gltf, k)

    # --- Render settings -------------------------------------------------------------------
    r = scene.render
    settings = render_settings(r.resolution_x, r.resolution_y, r.resolution_percentage, cycles.samples,
                               cycles.max_bounces)
    gltf.setdefault("extensions", {})["BRUME_render"] = settings
    use_extension(gltf, "BRUME_render")
    for name in ("diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces"):
        v = getattr(cycles, name)
        if v < cycles.max_bounces:
            report.warn("render settings: Cycles' %s = %d is below max_bounces = %d: brume has one depth for all "
                        "events (--max-depth %d)" % (name, v, cycles.max_bounces, settings["maxDepth"]))
    if cycles.sample_clamp_direct > 0 or cycles.sample_clamp_indirect > 0:
        report.warn("render settings: Cycles clamps samples (direct %.3g, indirect %.3g); brume does not"
                    % (cycles.sample_clamp_direct, cycles.sample_clamp_indirect))
    if r.use_border:
        report.warn("render settings: the render region is not exported (brume renders the whole frame)")

    tmp = filepath + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")
    os.replace(tmp, filepath)
    return report


def _vec3(x, y, z):
    import mathutils
    return mathutils.Vector((x, y, z))


def _world_polygon_area(pts):
    import mathutils
    total = mathutils.Vector((0.0, 0.0, 0.0))
    for i in range(1, len(pts) - 1):
        total += (pts[i] - pts[0]).cross(pts[i + 1] - pts[0])
    return 0.5 * total.length


# --------------------------------------------------------------------------------------------
# Add-on: File > Export > brume (.gltf)
# --------------------------------------------------------------------------------------------

if bpy is not None:
    from bpy_extras.io_utils import ExportHelper

    class EXPORT_SCENE_OT_brume(bpy.types.Operator, ExportHelper):
        """Export the scene for brume (glTF 2.0 with fog: BRUME_media)"""
        bl_idname = "export_scene.brume"
        bl_label = "Export brume"
        filename_ext = ".gltf"
        filter_glob: bpy.props.StringProperty(default="*.gltf", options={"HIDDEN"})

        def execute(self, context):
            report = Report()
            try:
                export_scene(self.filepath, context, report)
            except ExportError as e:
                self.report({"ERROR"}, str(e))
                return {"CANCELLED"}
            for w in report.warnings:
                self.report({"WARNING"}, w)
            return {"FINISHED"}

    def _menu(self, context):
        self.layout.operator(EXPORT_SCENE_OT_brume.bl_idname, text="brume (.gltf)")

    def register():
        bpy.utils.register_class(EXPORT_SCENE_OT_brume)
        bpy.types.TOPBAR_MT_file_export.append(_menu)

    def unregister():
        bpy.types.TOPBAR_MT_file_export.remove(_menu)
        bpy.utils.unregister_class(EXPORT_SCENE_OT_brume)


USAGE = "usage: blender -b SCENE.blend -P brume_export.py -- OUT.gltf"


def main(argv):
    if len(argv) != 1 or argv[0].startswith("-"):
        print("%s: error: %s" % (PROG, USAGE), file=sys.stderr)
        return 2
    try:
        report = export_scene(argv[0])
    except ExportError as e:
        print("%s: error: %s" % (PROG, e), file=sys.stderr)
        return 1
    print("%s: wrote %s (%d warning%s)" % (PROG, argv[0], len(report.warnings),
                                          "" if len(report.warnings) == 1 else "s"))
    return 0


if __name__ == "__main__" and bpy is not None and not bpy.app.background and "--" not in sys.argv:
    register()  # run from Blender's text editor: install the menu entry
elif __name__ == "__main__" and bpy is not None:
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    code = main(args)
    sys.stdout.flush()
    sys.stderr.flush()
    if code:
        os._exit(code)  # Blender would otherwise exit 0 after the script
