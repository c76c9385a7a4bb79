#!/usr/bin/python3
"""Writes a large test scene: a rippled ground of TRIANGLES triangles in fog, as one .glb.

Run: /usr/bin/python3 tests/data/make_big_mesh.py OUT.glb [TRIANGLES]
(default 10,000,000). Standard library only; the file is ~300 MB for 10M triangles, so it is
written to a temporary directory by the [long] test (tests/test_cli_big_mesh.cpp), never
committed. Deterministic.

The ground is a grid of NX x NZ quads (two triangles each) over x in [-20, 20], z in [-40, 0],
height y = -1.5 + 0.15 sin(1.7 x) sin(2.3 z), with per-vertex normals and uint32 indices,
front faces up, grey Lambertian. Camera at the origin looking down -Z (yfov 0.8, aspect
4:3), a point light (I = 40 W/sr) at (0, 1.5, -6), ambient fog (scattering 0.08,
absorption 0.01, g 0.3).
"""

import array
import json
import math
import struct
import sys

X0, X1, Z0, Z1 = -20.0, 20.0, -40.0, 0.0


def grid_size(triangles):
    """NX x NZ quads with 2 NX NZ >= triangles, NX : NZ = 1 : 1 (the ground is 40 x 40 m)."""
    n = int(math.ceil(math.sqrt(triangles / 2.0)))
    nz = n
    nx = int(math.ceil(triangles / (2.0 * nz)))
    return nx, nz


def vertices(nx, nz):
    xs = [X0 + (X1 - X0) * i / nx for i in range(nx + 1)]
    sx = [math.sin(1.7 * x) for x in xs]
    cx = [1.7 * 0.15 * math.cos(1.7 * x) for x in xs]
    pos = array.array("f")
    nrm = array.array("f")
    for j in range(nz + 1):
        z = Z0 + (Z1 - Z0) * j / nz
        sz, dz = math.sin(2.3 * z), 2.3 * 0.15 * math.cos(2.3 * z)
        row = [0.0] * (3 * (nx + 1))
        nrow = [0.0] * (3 * (nx + 1))
        for i, x in enumerate(xs):
            row[3 * i] = x
            row[3 * i + 1] = -1.5 + 0.15 * sx[i] * sz
            row[3 * i + 2] = z
            # normal of y = h(x, z): (-dh/dx, 1, -dh/dz), normalised
            hx, hz = cx[i] * sz, sx[i] * dz
            inv = 1.0 / math.sqrt(hx * hx + 1.0 + hz * hz)
            nrow[3 * i] = -hx * inv
            nrow[3 * i + 1] = inv
            nrow[3 * i + 2] = -hz * inv
        pos.extend(row)
        nrm.extend(nrow)
    return pos, nrm


def indices(nx, nz, triangles):
    """Two counter-clockwise (seen from +Y) triangles per quad, row by row; the last row may
    be cut short so that there are exactly `triangles`."""
    stride = nx + 1
    first = []  # the quads of row 0
    for i in range(nx):
        a, b = i, i + 1  # z = j
        c, d = i + stride, i + 1 + stride  # z = j + 1 (towards the camera)
        first += [a, c, b, b, c, d]
    idx = array.array("I")
    per_row = 6 * nx
    left = 3 * triangles
    for j in range(nz):
        if left <= 0:
            break
        off = j * stride
        take = min(per_row, left)
        idx.extend([v + off for v in first[:take]])
        left -= take
    return idx


def pad4(data, byte):
    return data + byte * ((4 - len(data) % 4) % 4)


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: make_big_mesh.py OUT.glb [TRIANGLES]")
    path = sys.argv[1]
    triangles = int(sys.argv[2]) if len(sys.argv) == 3 else 10_000_000
    nx, nz = grid_size(triangles)
    pos, nrm = vertices(nx, nz)
    idx = indices(nx, nz, triangles)
    if sys.byteorder != "little":
        for a in (pos, nrm, idx):
            a.byteswap()
    vcount = len(pos) // 3
    ys = pos[1::3]
    blobs = [pos.tobytes(), nrm.tobytes(), idx.tobytes()]
    views, offset = [], 0
    for blob, target in zip(blobs, (34962, 34962, 34963)):
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(blob), "target": target})
        offset += len(blob)
    doc = {
        "asset": {"version": "2.0", "generator": "brume tests/data/make_big_mesh.py"},
        "buffers": [{"byteLength": offset}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": vcount, "type": "VEC3",
             "min": [X0, min(ys), Z0], "max": [X1, max(ys), Z1]},
            {"bufferView": 1, "componentType": 5126, "count": vcount, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"},
        ],
        "materials": [{"name": "ground", "pbrMetallicRoughness": {
            "baseColorFactor": [0.6, 0.6, 0.6, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
        "meshes": [{"name": "ground", "primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0, "mode": 4}]}],
        "cameras": [{"name": "camera", "type": "perspective",
                     "perspective": {"yfov": 0.8, "aspectRatio": 4.0 / 3.0, "znear": 0.01}}],
        "extensions": {
            "KHR_lights_punctual": {"lights": [
                {"name": "light", "type": "point", "color": [1.0, 0.9, 0.8], "intensity": 40.0}]},
            "BRUME_media": {"ambient": 0, "media": [
                {"name": "fog", "scattering": [0.08, 0.08, 0.08], "absorption": [0.01, 0.01, 0.01],
                 "anisotropy": 0.3}]},
        },
        "extensionsUsed": ["KHR_lights_punctual", "BRUME_media"],
        "nodes": [
            {"name": "camera", "camera": 0},
            {"name": "light", "translation": [0.0, 1.5, -6.0],
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "ground", "mesh": 0},
        ],
        "scenes": [{"name": "scene", "nodes": [0, 1, 2]}],
        "scene": 0,
    }
    json_chunk = pad4(json.dumps(doc, separators=(",", ":")).encode(), b" ")
    total = 12 + 8 + len(json_chunk) + 8 + offset
    with open(path, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, total))
        f.write(struct.pack("<I4s", len(json_chunk), b"JSON"))
        f.write(json_chunk)
        f.write(struct.pack("<I4s", offset, b"BIN\0"))
        for blob in blobs:
            f.write(blob)
    print("%s: %d triangles, %d vertices, %d bytes" % (path, len(idx) // 3, vcount, total))


if __name__ == "__main__":
    main()
