# Denoising layers in Blender's compositor: brume renders a scene with --aov albedo,normal;
# Blender 3.4 loads the EXR, its Image node offers the passes "Albedo" and "Normal" (and
# "Combined"), and each pass, sent through the compositor to its Composite output and written
# by Blender, holds the values the file holds (both read here with OpenImageIO).
#
#   /usr/bin/python3 tests/blender/aov_layers.py --blender blender --brume build/brume
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(os.path.dirname(HERE), "data", "furnace_glowing.gltf")
W, H = 16, 12

# Run inside Blender: argv after "--": the EXR, the JSON to write (pass names and values).
INSIDE = r'''
import bpy, json, sys
exr, out = sys.argv[sys.argv.index("--") + 1:]
img = bpy.data.images.load(exr)
sc = bpy.context.scene
sc.render.engine = "CYCLES"
sc.cycles.samples = 1
sc.render.resolution_x, sc.render.resolution_y, sc.render.resolution_percentage = %d, %d, 100
sc.view_settings.view_transform = "Standard"
sc.use_nodes = True
nt = sc.node_tree
nt.nodes.clear()
node = nt.nodes.new("CompositorNodeImage")
node.image = img
comp = nt.nodes.new("CompositorNodeComposite")
sc.render.image_settings.file_format = "OPEN_EXR"
sc.render.image_settings.color_depth = "32"
res = {"type": img.type, "passes": [o.name for o in node.outputs], "files": {}}
for name in ("Albedo", "Normal"):
    if name not in node.outputs:
        continue
    nt.links.new(node.outputs[name], comp.inputs[0])
    sc.render.filepath = out + "." + name + ".exr"
    bpy.ops.render.render(write_still=True)
    res["files"][name] = sc.render.filepath
json.dump(res, open(out, "w"))
''' % (W, H)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--brume", required=True)
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="brume-blender-aov-")
    failures = []

    def check(cond, what):
        print(("ok: " if cond else "FAIL: ") + what)
        if not cond:
            failures.append(what)

    try:
        exr = os.path.join(work, "aov.exr")
        subprocess.run([a.brume, "render", SCENE, "-o", exr, "--res", "%dx%d" % (W, H), "--spp", "2",
                        "--aov", "albedo,normal"], check=True, stdout=subprocess.DEVNULL)
        inp = oiio.ImageInput.open(exr)
        names = list(inp.spec().channelnames)
        px = np.asarray(inp.read_image(format="float")).reshape(H, W, -1)
        inp.close()
        script = os.path.join(work, "inside.py")
        with open(script, "w") as f:
            f.write(INSIDE)
        out = os.path.join(work, "blender.json")
        p = subprocess.run([a.blender, "-b", "--factory-startup", "--python-exit-code", "1", "-P", script, "--", exr, out],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        check(p.returncode == 0, "Blender loads the EXR and runs the compositor (exit %d)" % p.returncode)
        if p.returncode != 0:
            sys.stderr.write(p.stdout[-2000:] + p.stderr[-2000:])
            return 1
        res = json.load(open(out))
        check(res["type"] == "MULTILAYER", "Blender reads a multilayer EXR (%s)" % res["type"])
        for name in ("Combined", "Albedo", "Normal"):
            check(name in res["passes"], "the Image node offers pass '%s' (passes: %s)" % (name, res["passes"]))
        for name, first in (("Albedo", "Albedo.R"), ("Normal", "Normal.X")):
            if name not in res["files"]:
                continue
            c = names.index(first)
            want = px[:, :, c:c + 3]
            b = oiio.ImageInput.open(res["files"][name])
            got = np.asarray(b.read_image(format="float")).reshape(H, W, -1)[:, :, :3] if b else None
            if b:
                b.close()
            err = float(np.abs(got - want).max()) if got is not None and got.shape == want.shape else float("inf")
            check(err < 1e-5, "pass '%s' through the compositor equals the file's %s.* (max difference %g)"
                  % (name, name, err))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("aov_layers: " + ("FAIL" if failures else "ok"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
