"""Small glTF 2.0 writer for brume scenes (Python 3 standard library only).

A GltfBuilder collects meshes, materials, nodes, a camera, KHR_lights_punctual lights and the
BRUME_media root extension, and writes one self-contained .gltf file: all binary data goes into
a single buffer embedded as a base64 data URI. The JSON is written with sorted keys and a
2-space indent, so the same script always produces the same bytes.

Conventions (see docs/scene-format.md): right-handed, +Y up, metres; cameras and lights look
down their node's local -Z; counter-clockwise triangles are front faces.

Geometry helpers at the bottom (box, quad, uv_sphere) return plain Python lists that
GltfBuilder.add_mesh accepts.
"""

import base64
import json
import math
import struct

# glTF enums
_FLOAT = 5126
_UNSIGNED_SHORT = 5123
_UNSIGNED_INT = 5125
_ARRAY_BUFFER = 34962
_ELEMENT_ARRAY_BUFFER = 34963


# ---------------------------------------------------------------------------------------------
# Small vector / quaternion helpers (tuples of floats)

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    n = math.sqrt(dot(a, a))
    if n == 0:
        raise ValueError("cannot normalize a zero vector")
    return (a[0] / n, a[1] / n, a[2] / n)


def quat_axis_angle(axis, angle):
    """glTF quaternion [x, y, z, w] rotating by `angle` radians about `axis` (right-handed)."""
    ax = normalize(axis)
    s = math.sin(0.5 * angle)
    return [ax[0] * s, ax[1] * s, ax[2] * s, math.cos(0.5 * angle)]


def quat_rotate(q, v):
    """Rotate vector v by glTF quaternion q = [x, y, z, w] (unit)."""
    u = (q[0], q[1], q[2])
    w = q[3]
    t = scale(cross(u, v), 2.0)
    return add(add(v, scale(t, w)), cross(u, t))


def quat_from_basis(right, up, back):
    """Quaternion of the rotation whose matrix columns are the local X, Y, Z axes in world space."""
    m00, m10, m20 = right
    m01, m11, m21 = up
    m02, m12, m22 = back
    tr = m00 + m11 + m22
    if tr > 0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = [(m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25 * s]
    elif m00 > m11 and m00 > m22:
        s = 2.0 * math.sqrt(1.0 + m00 - m11 - m22)
        q = [0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s]
    elif m11 > m22:
        s = 2.0 * math.sqrt(1.0 + m11 - m00 - m22)
        q = [(m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + m22 - m00 - m11)
        q = [(m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s]
    if q[3] < 0:  # canonical sign
        q = [-c for c in q]
    n = math.sqrt(sum(c * c for c in q))
    return [c / n + 0.0 for c in q]  # + 0.0 turns -0.0 into 0.0


def quat_look_dir(forward, up_hint=(0.0, 1.0, 0.0)):
    """Rotation that maps the local -Z axis onto `forward`, local +Y as close to `up_hint`."""
    f = normalize(forward)
    if abs(dot(f, normalize(up_hint))) > 0.999999:
        up_hint = (0.0, 0.0, -1.0) if f[1] < 0 else (0.0, 0.0, 1.0)
    right = normalize(cross(f, up_hint))
    up = cross(right, f)
    back = scale(f, -1.0)
    return quat_from_basis(right, up, back)


def quat_look_at(eye, target, up_hint=(0.0, 1.0, 0.0)):
    return quat_look_dir(sub(target, eye), up_hint)


def _floats(values):
    """Plain floats for JSON, rounded to 12 decimals (so 4.6 - 1.0 is written 3.6), with -0.0
    written as 0.0."""
    return [round(float(c), 12) + 0.0 for c in values]


# ---------------------------------------------------------------------------------------------
# The builder

class GltfBuilder:
    def __init__(self, generator="brume scenes/gltfgen.py"):
        self.generator = generator
        self.buffer = bytearray()
        self.buffer_views = []
        self.accessors = []
        self.meshes = []
        self.materials = []
        self.nodes = []
        self.root_nodes = []
        self.cameras = []
        self.lights = []
        self.media = None
        self.ambient = None
        self.extensions_used = set()

    # -- binary data ---------------------------------------------------------------------------

    def _add_view(self, data, target):
        while len(self.buffer) % 4:
            self.buffer.append(0)
        view = {"buffer": 0, "byteOffset": len(self.buffer), "byteLength": len(data)}
        if target is not None:
            view["target"] = target
        self.buffer.extend(data)
        self.buffer_views.append(view)
        return len(self.buffer_views) - 1

    def _add_float_accessor(self, rows, type_name, width, with_bounds=False):
        flat = []
        for r in rows:
            if len(r) != width:
                raise ValueError("expected %d components, got %r" % (width, r))
            flat.extend(float(c) for c in r)
        data = struct.pack("<%df" % len(flat), *flat)
        view = self._add_view(data, _ARRAY_BUFFER)
        acc = {"bufferView": view, "componentType": _FLOAT, "count": len(rows), "type": type_name}
        if with_bounds:
            # min/max of the values as stored (float32), as the glTF spec requires for POSITION
            stored = struct.unpack("<%df" % len(flat), data)
            acc["min"] = [min(stored[i::width]) for i in range(width)]
            acc["max"] = [max(stored[i::width]) for i in range(width)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def _add_index_accessor(self, indices, vertex_count):
        for i in indices:
            if not 0 <= i < vertex_count:
                raise ValueError("index %d out of range (%d vertices)" % (i, vertex_count))
        if vertex_count <= 65535:
            data = struct.pack("<%dH" % len(indices), *indices)
            ctype = _UNSIGNED_SHORT
        else:
            data = struct.pack("<%dI" % len(indices), *indices)
            ctype = _UNSIGNED_INT
        view = self._add_view(data, _ELEMENT_ARRAY_BUFFER)
        self.accessors.append({"bufferView": view, "componentType": ctype, "count": len(indices),
                               "type": "SCALAR"})
        return len(self.accessors) - 1

    # -- materials -----------------------------------------------------------------------------

    def add_material(self, name, base_color=(0.8, 0.8, 0.8), metallic=0.0, roughness=1.0,
                     emissive=None, emissive_strength=None, double_sided=False):
        """Metallic-roughness material. metallicFactor is always written (glTF default is 1).
        Radiance of an emissive material = emissive x emissive_strength [W/(m^2 sr)]; an
        `emissive` above 1 is written as emissiveFactor <= 1 times KHR_materials_emissive_strength."""
        pbr = {"baseColorFactor": [float(c) for c in base_color] + [1.0],
               "metallicFactor": float(metallic), "roughnessFactor": float(roughness)}
        mat = {"name": name, "pbrMetallicRoughness": pbr}
        if emissive is not None:
            # glTF limits emissiveFactor to [0, 1]: move any excess into the strength
            peak = max(float(c) for c in emissive)
            if peak > 1.0:
                emissive = [float(c) / peak for c in emissive]
                emissive_strength = peak * (1.0 if emissive_strength is None else emissive_strength)
            mat["emissiveFactor"] = [float(c) for c in emissive]
        if emissive_strength is not None and emissive_strength != 1.0:
            mat["extensions"] = {"KHR_materials_emissive_strength": {
                "emissiveStrength": float(emissive_strength)}}
            self.extensions_used.add("KHR_materials_emissive_strength")
        if double_sided:
            mat["doubleSided"] = True
        self.materials.append(mat)
        return len(self.materials) - 1

    # -- meshes --------------------------------------------------------------------------------

    def add_mesh(self, name, positions, indices, normals=None, uvs=None, material=None,
                 interior=None):
        """One mesh with one triangle primitive. `interior` (a media index) marks it as a closed
        BRUME_media boundary. Returns the mesh index (place it with add_node)."""
        if len(indices) % 3:
            raise ValueError("index count %d is not a multiple of 3" % len(indices))
        n = len(positions)
        attributes = {"POSITION": self._add_float_accessor(positions, "VEC3", 3, with_bounds=True)}
        if normals is not None:
            if len(normals) != n:
                raise ValueError("normals and positions differ in count")
            attributes["NORMAL"] = self._add_float_accessor([normalize(v) for v in normals], "VEC3", 3)
        if uvs is not None:
            if len(uvs) != n:
                raise ValueError("uvs and positions differ in count")
            attributes["TEXCOORD_0"] = self._add_float_accessor(uvs, "VEC2", 2)
        prim = {"attributes": attributes, "indices": self._add_index_accessor(indices, n), "mode": 4}
        if material is not None:
            prim["material"] = material
        mesh = {"name": name, "primitives": [prim]}
        if interior is not None:
            mesh["extensions"] = {"BRUME_media": {"interior": int(interior)}}
            self.extensions_used.add("BRUME_media")
        self.meshes.append(mesh)
        return len(self.meshes) - 1

    # -- nodes ---------------------------------------------------------------------------------

    def add_node(self, name, mesh=None, translation=None, rotation=None, scale=None,
                 children=None, root=True):
        """A node with optional TRS (rotation is a glTF quaternion [x, y, z, w])."""
        node = {"name": name}
        if mesh is not None:
            node["mesh"] = mesh
        if translation is not None:
            node["translation"] = _floats(translation)
        if rotation is not None:
            node["rotation"] = _floats(rotation)
        if scale is not None:
            node["scale"] = _floats(scale)
        if children:
            node["children"] = list(children)
        self.nodes.append(node)
        index = len(self.nodes) - 1
        if root:
            self.root_nodes.append(index)
        return index

    def add_camera(self, name, yfov, aspect_ratio, translation=(0, 0, 0), rotation=None,
                   znear=0.01, zfar=None):
        """A perspective camera node looking down its local -Z."""
        cam = {"name": name, "type": "perspective",
               "perspective": {"yfov": float(yfov), "aspectRatio": float(aspect_ratio),
                               "znear": float(znear)}}
        if zfar is not None:
            cam["perspective"]["zfar"] = float(zfar)
        self.cameras.append(cam)
        node = self.add_node(name, translation=translation, rotation=rotation)
        self.nodes[node]["camera"] = len(self.cameras) - 1
        return node

    def add_light(self, name, kind, color, intensity, translation=(0, 0, 0), rotation=None,
                  radius=None, inner_cone=None, outer_cone=None):
        """A KHR_lights_punctual light on its own node. kind: "point", "spot" or "directional".
        Point/spot: I = color x intensity [W/sr]; directional: E = color x intensity [W/m^2].
        radius > 0 (extras.radius) makes a point light a sphere light."""
        if kind not in ("point", "spot", "directional"):
            raise ValueError("unknown light type %r" % kind)
        light = {"name": name, "type": kind, "color": [float(c) for c in color],
                 "intensity": float(intensity)}
        if kind == "spot":
            spot = {}
            if inner_cone is not None:
                spot["innerConeAngle"] = float(inner_cone)
            if outer_cone is not None:
                spot["outerConeAngle"] = float(outer_cone)
            light["spot"] = spot
        if radius is not None:
            light["extras"] = {"radius": float(radius)}
        self.lights.append(light)
        self.extensions_used.add("KHR_lights_punctual")
        node = self.add_node(name, translation=translation, rotation=rotation)
        self.nodes[node]["extensions"] = {"KHR_lights_punctual": {"light": len(self.lights) - 1}}
        return node

    # -- media ---------------------------------------------------------------------------------

    def add_medium(self, name, scattering, absorption, anisotropy=0.0, density=None, emission=None, blackbody=None):
        """A medium (coefficients in 1/m per RGB channel, HG g). Returns its index. density:
        None (homogeneous) or {"uri": "x.vdb", "grid": "density", "scale": 1.0}, a density
        grid the coefficients are per unit of (docs/scene-format.md). emission: None, a grey
        value or RGB triple (radiance per metre), or {"rgb": [...], "uri": ..., "grid": ...,
        "scale": ...} for an emission grid. blackbody: None or its object ({"temperature": K} or
        a temperature grid {"uri", "grid", "scale"}, with "intensity" and "tint")."""
        def rgb(v):
            if isinstance(v, (int, float)):
                return [float(v)] * 3
            return [float(c) for c in v]
        if self.media is None:
            self.media = []
        medium = {"name": name, "scattering": rgb(scattering), "absorption": rgb(absorption),
                  "anisotropy": float(anisotropy)}
        if density is not None:
            medium["density"] = dict(density)
        if isinstance(emission, dict):
            medium["emission"] = dict(emission)
        elif emission is not None:
            medium["emission"] = rgb(emission)
        if blackbody is not None:
            medium["blackbody"] = dict(blackbody)
        self.media.append(medium)
        self.extensions_used.add("BRUME_media")
        return len(self.media) - 1

    def set_ambient(self, medium):
        """The medium that fills all space outside bounded media (None = vacuum)."""
        self.ambient = medium

    # -- output --------------------------------------------------------------------------------

    def document(self):
        doc = {"asset": {"version": "2.0", "generator": self.generator}}
        if self.buffer:
            uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(self.buffer)).decode("ascii")
            doc["buffers"] = [{"byteLength": len(self.buffer), "uri": uri}]
            doc["bufferViews"] = self.buffer_views
            doc["accessors"] = self.accessors
        for key, value in (("meshes", self.meshes), ("materials", self.materials),
                           ("nodes", self.nodes), ("cameras", self.cameras)):
            if value:
                doc[key] = value
        doc["scene"] = 0
        doc["scenes"] = [{"name": "scene", "nodes": list(self.root_nodes)}]
        ext = {}
        if self.lights:
            ext["KHR_lights_punctual"] = {"lights": self.lights}
        if self.media is not None:
            media_ext = {"media": self.media}
            if self.ambient is not None:
                media_ext["ambient"] = int(self.ambient)
            ext["BRUME_media"] = media_ext
        elif self.ambient is not None:
            raise ValueError("ambient medium set but no media defined")
        if ext:
            doc["extensions"] = ext
        if self.extensions_used:
            doc["extensionsUsed"] = sorted(self.extensions_used)
        return doc

    def to_json(self):
        return json.dumps(self.document(), sort_keys=True, indent=2, allow_nan=False) + "\n"

    def write(self, path):
        text = self.to_json()
        json.loads(text)  # must round-trip
        with open(path, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
        return path


# ---------------------------------------------------------------------------------------------
# Geometry helpers. Each returns (positions, normals, uvs, indices) with counter-clockwise
# front faces as described.

def box(size, center=(0.0, 0.0, 0.0)):
    """Axis-aligned box with flat normals, front faces outward. size = (sx, sy, sz)."""
    hx, hy, hz = 0.5 * size[0], 0.5 * size[1], 0.5 * size[2]
    positions, normals, uvs, indices = [], [], [], []
    # (normal, u axis, v axis): u x v = normal, so the corner order below is counter-clockwise
    faces = [((1, 0, 0), (0, 0, -1), (0, 1, 0)),
             ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
             ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
             ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
             ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
             ((0, 0, -1), (-1, 0, 0), (0, 1, 0))]
    half = (hx, hy, hz)
    for n, u, v in faces:
        base = len(positions)
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            p = tuple((n[i] + su * u[i] + sv * v[i]) * half[i] + center[i] for i in range(3))
            positions.append(p)
            normals.append(tuple(float(c) for c in n))
            uvs.append((0.5 * (su + 1), 0.5 * (1 - sv)))
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return positions, normals, uvs, indices


def quad(center, u_half, v_half):
    """Rectangle center ± u_half ± v_half, two triangles; front face normal = u_half x v_half."""
    n = normalize(cross(u_half, v_half))
    positions, uvs = [], []
    for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
        positions.append(add(center, add(scale(u_half, su), scale(v_half, sv))))
        uvs.append((0.5 * (su + 1), 0.5 * (1 - sv)))
    return positions, [n] * 4, uvs, [0, 1, 2, 0, 2, 3]


def uv_sphere(radius, segments, rings, center=(0.0, 0.0, 0.0), inward=False):
    """Latitude-longitude sphere: `segments` around Y, `rings` from pole to pole, one vertex per
    pole, vertices exactly on the sphere (an inscribed polyhedron). Vertices are shared, so the
    mesh is closed. Front faces point outward, or towards the centre when inward=True.
    Normals are the smooth radial directions (pointing the same way as the front faces)."""
    if segments < 3 or rings < 2:
        raise ValueError("sphere needs segments >= 3 and rings >= 2")
    positions, normals, uvs = [], [], []
    sgn = -1.0 if inward else 1.0

    def push(d, u, v):
        positions.append(add(center, scale(d, radius)))
        normals.append(scale(d, sgn))
        uvs.append((u, v))

    push((0.0, 1.0, 0.0), 0.5, 0.0)  # north pole, index 0
    for i in range(1, rings):
        theta = math.pi * i / rings
        st, ct = math.sin(theta), math.cos(theta)
        for j in range(segments):
            phi = 2.0 * math.pi * j / segments
            push((st * math.cos(phi), ct, -st * math.sin(phi)), j / segments, i / rings)
    south = len(positions)
    push((0.0, -1.0, 0.0), 0.5, 1.0)

    def ring(i, j):  # vertex of ring i (1..rings-1), segment j (wraps)
        return 1 + (i - 1) * segments + (j % segments)

    tris = []
    # phi runs counter-clockwise seen from +Y (x = cos phi, z = -sin phi), so these triangles
    # are counter-clockwise seen from outside; inward=True reverses each one.
    for j in range(segments):
        tris.append((0, ring(1, j), ring(1, j + 1)))
    for i in range(1, rings - 1):
        for j in range(segments):
            a, b = ring(i, j), ring(i, j + 1)
            c, d = ring(i + 1, j), ring(i + 1, j + 1)
            tris.append((a, c, d))
            tris.append((a, d, b))
    for j in range(segments):
        tris.append((south, ring(rings - 1, j + 1), ring(rings - 1, j)))
    indices = []
    for t in tris:
        indices += [t[0], t[2], t[1]] if inward else list(t)
    return positions, normals, uvs, indices


# ---------------------------------------------------------------------------------------------
# Checks

def triangle_normal(positions, indices, t):
    a, b, c = (positions[indices[3 * t + k]] for k in range(3))
    return cross(sub(b, a), sub(c, a))


def signed_volume(positions, indices):
    """Signed volume enclosed by a closed triangle mesh: > 0 when front faces point outward."""
    v = 0.0
    for t in range(len(indices) // 3):
        a, b, c = (positions[indices[3 * t + k]] for k in range(3))
        v += dot(a, cross(b, c)) / 6.0
    return v


def check_closed(indices):
    """Every directed edge is matched by exactly one opposite edge (closed, consistently wound)."""
    edges = {}
    for t in range(len(indices) // 3):
        tri = indices[3 * t:3 * t + 3]
        for k in range(3):
            e = (tri[k], tri[(k + 1) % 3])
            edges[e] = edges.get(e, 0) + 1
    for (a, b), n in edges.items():
        if n != 1 or edges.get((b, a)) != 1:
            raise AssertionError("edge %d-%d is not shared by exactly two opposite triangles" % (a, b))
