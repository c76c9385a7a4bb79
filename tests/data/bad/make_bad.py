#!/usr/bin/python3
"""Writes the corpus of bad scene files in tests/data/bad/ (for tests/test_cli_bad_inputs.cpp).

Run: /usr/bin/python3 tests/data/bad/make_bad.py
Standard library (and scenes/gltfgen.py) for the glTF files; the bad density grids (.vdb)
need Debian's python3-openvdb. Deterministic glTF output. Each file starts from
the same small valid scene (a camera looking at a grey quad in fog, lit by a point light) and
breaks exactly one thing, named by the file and described by the function that writes it. The
test runs brume on each and expects a one-line error naming the file and the problem; a file
added here needs a case there (the test checks that every file in this directory has one).
"""

import json
import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "..", "scenes"))

sys.dont_write_bytecode = True  # no __pycache__ next to the scenes
import gltfgen as g  # noqa: E402

GENERATOR = "brume tests/data/bad/make_bad.py"


def base(camera=True, texture_uv=False):
    """The valid scene every bad file is made from: accessor 0 holds the quad's 4 positions,
    the last accessor its 6 indices; bufferView 0 the positions."""
    b = g.GltfBuilder(GENERATOR)
    if camera:
        b.add_camera("camera", yfov=0.8, aspect_ratio=1.0, translation=(0.0, 0.0, 2.0))
    b.set_ambient(b.add_medium("fog", 0.1, 0.01, 0.3))
    grey = b.add_material("grey", base_color=(0.5, 0.5, 0.5))
    pos, nrm, uvs, idx = g.quad((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0))
    mesh = b.add_mesh("quad", pos, idx, uvs=uvs if texture_uv else None, material=grey)
    b.add_node("quad", mesh=mesh)
    b.add_light("lamp", "point", (1.0, 1.0, 1.0), 5.0, translation=(0.0, 1.0, 1.0))
    return b


def write_json(name, doc):
    text = json.dumps(doc, sort_keys=True, indent=2, allow_nan=False) + "\n"
    with open(os.path.join(HERE, name), "w", encoding="utf-8", newline="\n") as f:
        f.write(text)
    return text


def write_bytes(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def glb(doc, binary):
    """A binary glTF container: a JSON chunk and a BIN chunk, each padded to 4 bytes."""
    text = json.dumps(doc, sort_keys=True, separators=(",", ":")).encode("utf-8")
    text += b" " * (-len(text) % 4)
    binary = bytes(binary) + b"\0" * (-len(binary) % 4)
    body = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def valid_base():
    """The base scene itself, valid: the test renders it to show that each bad file fails
    for its one breakage alone."""
    write_json("valid_base.gltf", base().document())


def truncated_glb():
    """The base scene as a .glb (JSON and BIN chunks), cut off halfway."""
    b = base()
    doc = b.document()
    doc["buffers"] = [{"byteLength": len(b.buffer)}]  # the GLB's own BIN chunk
    whole = glb(doc, b.buffer)
    write_bytes("truncated.glb", whole[:len(whole) // 2])


def broken_json():
    """The base scene's JSON text, cut off halfway."""
    text = base().to_json()
    write_bytes("broken_json.gltf", text[:len(text) // 2].encode("utf-8"))


def buffer_view_out_of_range():
    """bufferViews[0] (48 bytes of positions) starts 8 bytes before the buffer's end."""
    doc = base().document()
    doc["bufferViews"][0]["byteOffset"] = doc["buffers"][0]["byteLength"] - 8
    write_json("buffer_view_out_of_range.gltf", doc)


def index_out_of_range():
    """Index 4 of the quad's 6 is 7; it has 4 vertices."""
    b = base()
    view = b.buffer_views[b.accessors[-1]["bufferView"]]
    struct.pack_into("<H", b.buffer, view["byteOffset"] + 2 * 4, 7)  # index 4 of 6: vertex 7 of 4
    write_json("index_out_of_range.gltf", b.document())


def nan_position():
    """Vertex 1's y is NaN (in the buffer; min/max stay finite)."""
    b = base()
    view = b.buffer_views[b.accessors[0]["bufferView"]]
    struct.pack_into("<f", b.buffer, view["byteOffset"] + 4 * 4, math.nan)  # vertex 1, y
    write_json("nan_position.gltf", b.document())


def missing_texture():
    """The quad's base colour texture is no_such_texture.png, which does not exist."""
    b = base(texture_uv=True)
    doc = b.document()
    doc["images"] = [{"uri": "no_such_texture.png"}]
    doc["textures"] = [{"source": 0}]
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    write_json("missing_texture.gltf", doc)


def orthographic_camera():
    """The only camera is orthographic."""
    doc = base().document()
    doc["cameras"][0] = {"type": "orthographic",
                         "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 0.01, "zfar": 100.0}}
    write_json("orthographic_camera.gltf", doc)


def no_camera():
    """No camera at all."""
    write_json("no_camera.gltf", base(camera=False).document())


def medium_out_of_range():
    """The quad's mesh encloses BRUME_media medium 3; there is only medium 0."""
    doc = base().document()
    doc["meshes"][0]["extensions"] = {"BRUME_media": {"interior": 3}}  # only medium 0 exists
    write_json("medium_out_of_range.gltf", doc)


def cyclic_nodes():
    """The quad's node is its own grandchild: nodes 1 -> 3 -> 1."""
    doc = base().document()
    doc["nodes"].append({"name": "loop", "children": [1]})
    doc["nodes"][1]["children"] = [len(doc["nodes"]) - 1]
    write_json("cyclic_nodes.gltf", doc)


def grid(name, values, vector=False, frustum=False, nan_at=None):
    """A small .vdb holding one grid "density" over voxels (0..3)^3 (values: a callable of
    (i, j, k)), a vec3 grid if vector, with a frustum transform if frustum, a NaN at voxel
    nan_at (set afterwards: copyFromArray leaves NaNs out)."""
    import numpy as np
    import pyopenvdb as vdb
    if vector:
        arr = np.ones((4, 4, 4, 3), dtype=np.float32)
        gr = vdb.Vec3SGrid()
    else:
        arr = np.fromfunction(values, (4, 4, 4), dtype=np.float32).astype(np.float32)
        gr = vdb.FloatGrid()
    gr.copyFromArray(arr, ijk=(0, 0, 0), tolerance=(0, 0, 0) if vector else 0)
    gr.name = "density"
    if nan_at is not None:
        gr.getAccessor().setValueOn(nan_at, float("nan"))
    if frustum:
        gr.transform = vdb.createFrustumTransform(xyzMin=(0, 0, 0), xyzMax=(4, 4, 4), taper=0.5, depth=2.0)
    else:
        gr.transform = vdb.createLinearTransform(voxelSize=0.25)
    vdb.write(os.path.join(HERE, name), grids=[gr])


def with_grid(name, uri, grid_name=None, scale=None):
    """The base scene with its fog given a density grid."""
    doc = base().document()
    density = {"uri": uri}
    if grid_name is not None:
        density["grid"] = grid_name
    if scale is not None:
        density["scale"] = scale
    doc["extensions"]["BRUME_media"]["media"][0]["density"] = density
    write_json(name, doc)


def bad_grids():
    """Density grids: a missing file, a file that is not OpenVDB, a missing grid name, a vec3
    grid, negative, NaN and infinite voxels, a frustum (non-affine) transform, a negative scale, a
    scale that makes one voxel's optical depth 1.4e6 (beyond the limit of 1e4)."""
    import numpy as np
    grid("smoke_ok.vdb", lambda i, j, k: 0.5 + 0.0 * i)
    grid("negative.vdb", lambda i, j, k: 0.5 - (i == 2) * (j == 1) * (k == 3) * 1.5)
    grid("nan.vdb", lambda i, j, k: 0.5 + 0.0 * i, nan_at=(1, 1, 1))
    grid("infinite.vdb", lambda i, j, k: np.where((i == 1) & (j == 2) & (k == 3), np.inf, 0.5))
    grid("vector.vdb", None, vector=True)
    grid("frustum.vdb", lambda i, j, k: 0.5 + 0.0 * i, frustum=True)
    with open(os.path.join(HERE, "not_a_grid.vdb"), "w") as f:
        f.write("this is not an OpenVDB file\n")
    with_grid("grid_missing_file.gltf", "no_such_smoke.vdb")
    with_grid("grid_not_vdb.gltf", "not_a_grid.vdb")
    with_grid("grid_missing_name.gltf", "smoke_ok.vdb", grid_name="temperature")
    with_grid("grid_vector.gltf", "vector.vdb", grid_name="density")
    with_grid("grid_negative_voxel.gltf", "negative.vdb")
    with_grid("grid_nan_voxel.gltf", "nan.vdb")
    with_grid("grid_infinite_voxel.gltf", "infinite.vdb")
    with_grid("grid_frustum.gltf", "frustum.vdb")
    with_grid("grid_negative_scale.gltf", "smoke_ok.vdb", scale=-2.0)
    with_grid("grid_too_dense.gltf", "smoke_ok.vdb", scale=1e8)


def with_fog(name, **fields):
    """The base scene with fields set in its fog medium (a value None removes the field)."""
    doc = base().document()
    fog = doc["extensions"]["BRUME_media"]["media"][0]
    for key, value in fields.items():
        if value is None:
            fog.pop(key, None)
        else:
            fog[key] = value
    write_json(name, doc)


def bad_emission():
    """Emissive media: a negative emission, a blackbody intensity out of [0, 1], a blackbody grid
    beside emission, a blackbody with neither temperature nor grid, a missing emission
    grid file; an ambient fog that would emit out to infinity: with no extinction in a channel
    it emits in, or with a density grid and emission without one."""
    with_fog("emission_negative.gltf", emission=[0.2, -0.5, 0.2])
    with_fog("blackbody_intensity.gltf", blackbody={"temperature": 1500.0, "intensity": 2.0})
    with_fog("blackbody_and_emission.gltf", emission=[0.1, 0.1, 0.1],
             blackbody={"uri": "smoke_ok.vdb", "grid": "density", "scale": 1000.0})
    with_fog("blackbody_empty.gltf", blackbody={"intensity": 1.0})
    with_fog("emission_missing_grid.gltf", emission={"rgb": [1.0, 0.5, 0.1], "uri": "no_such_fire.vdb"})
    with_fog("emission_ambient_clear.gltf", emission=[0.1, 0.1, 0.1], scattering=[0.1, 0.0, 0.1],
             absorption=[0.0, 0.0, 0.0])
    with_fog("emission_ambient_grid.gltf", emission=[0.1, 0.1, 0.1], density={"uri": "smoke_ok.vdb"})


def bad_light_surfaces():
    """Material extras of light surfaces: cameraVisible false on an opaque material, and
    transparent given as a string."""
    b = base()
    b.materials[0]["extras"] = {"cameraVisible": False}
    write_json("camera_invisible_opaque.gltf", b.document())
    b = base()
    b.materials[0]["extras"] = {"transparent": "yes"}
    write_json("transparent_not_bool.gltf", b.document())


def main():
    valid_base()
    truncated_glb()
    broken_json()
    buffer_view_out_of_range()
    index_out_of_range()
    nan_position()
    missing_texture()
    orthographic_camera()
    no_camera()
    medium_out_of_range()
    cyclic_nodes()
    bad_grids()
    bad_emission()
    bad_light_surfaces()


if __name__ == "__main__":
    main()
