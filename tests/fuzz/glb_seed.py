#!/usr/bin/env python3
"""Writes a .gltf scene as a binary glTF (GLB) seed for the loader's fuzzer: its first buffer,
a base64 data: URI, moves into the BIN chunk. Usage: glb_seed.py IN.gltf OUT.glb"""
import base64
import json
import struct
import sys

gltf = json.load(open(sys.argv[1]))
buffer = gltf["buffers"][0]
data = base64.b64decode(buffer.pop("uri").split(",", 1)[1])
text = json.dumps(gltf, separators=(",", ":")).encode()
text += b" " * (-len(text) % 4)
data += b"\0" * (-len(data) % 4)
chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(data), 0x004E4942) + data
with open(sys.argv[2], "wb") as out:
    out.write(b"glTF" + struct.pack("<II", 2, 12 + len(chunks)) + chunks)
