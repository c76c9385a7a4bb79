# Equal-time comparison with Cycles (a measurement, not a test: docs/results.md): builds a
# round-trip scene (make_scenes.py) at a given size, exports it, renders it with Cycles for T
# seconds (its time limit, samples unbounded, render time only), with brume for T seconds
# (--time), and with brume for R seconds as the reference, on the same threads; prints each
# image's relative MSE against the reference, per pixel (x - ref)^2 / (ref^2 + 0.01), the
# mean over the image, and their ratio.
#
#   /usr/bin/python3 tests/blender/equal_time.py NAME --blender blender --brume build/brume \
#       [--seconds 30] [--reference 240] [--width 160 --height 120] [--threads 2] [--workdir DIR]
import argparse
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import compare  # noqa: E402
import roundtrip  # noqa: E402


def rel_mse(img, ref):
    return float(np.mean((img - ref) ** 2 / (ref ** 2 + 0.01)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("name")
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--brume", required=True)
    ap.add_argument("--seconds", type=float, default=30)
    ap.add_argument("--reference", type=float, default=240)
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=120)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--workdir", default="/tmp/brume-equal-time")
    a = ap.parse_args()
    w, n = a.workdir, a.name
    os.makedirs(w, exist_ok=True)
    blend, gltf = os.path.join(w, n + ".blend"), os.path.join(w, n + ".gltf")
    roundtrip.run([a.blender, "-b", "--factory-startup", "--python-exit-code", "1", "-P",
                   os.path.join(HERE, "make_scenes.py"), "--", w, "--width", str(a.width), "--height", str(a.height),
                   "--samples", "100000", "--threads", str(a.threads), n], "scene build", os.path.join(w, n + ".make.log"))
    roundtrip.run([a.blender, "-b", blend, "--python-exit-code", "1", "-P", roundtrip.EXPORTER, "--", gltf], "export",
                  os.path.join(w, n + ".export.log"))
    cy = os.path.join(w, n + ".cycles.exr")
    expr = ["import bpy", "s = bpy.context.scene", "s.render.filepath = %r" % cy, "s.cycles.time_limit = %g" % a.seconds,
            "s.render.threads = %d" % a.threads, "bpy.ops.render.render(write_still=True)"]
    roundtrip.run([a.blender, "-b", blend, "--python-exit-code", "1", "--python-expr", "; ".join(expr)],
                  "Cycles render", os.path.join(w, n + ".cycles.log"))
    images = {"cycles": compare.load_exr(cy)}
    for label, secs in (("brume", a.seconds), ("reference", a.reference)):
        out = os.path.join(w, "%s.%s.exr" % (n, label))
        p = subprocess.run([a.brume, "render", gltf, "-o", out, "--time", str(secs), "--threads", str(a.threads),
                            "--seed", "7" if label == "reference" else "1"], capture_output=True, text=True)
        if p.returncode != 0:
            raise SystemExit(p.stderr)
        print("%s: %s" % (label, p.stdout.strip().splitlines()[0]))
        images[label] = compare.load_exr(out)
    ref = images["reference"]
    e = {k: rel_mse(images[k], ref) for k in ("cycles", "brume")}
    print("%s at %g s, %d threads, %dx%d: relMSE Cycles %.4g, brume %.4g: brume's is %.1fx lower "
          "(reference: brume %g s; image means Cycles %.5f, brume %.5f, reference %.5f)"
          % (n, a.seconds, a.threads, a.width, a.height, e["cycles"], e["brume"], e["cycles"] / e["brume"],
             a.reference, images["cycles"].mean(), images["brume"].mean(), ref.mean()))


if __name__ == "__main__":
    main()
