# Round-trip test: build a scene in Blender (make_scenes.py), render it with Cycles, export it
# with src/blender/brume_export.py, render the export with brume at the settings the export
# carries (BRUME_render: size, spp, depth), and compare the images (compare.py).
#
#   /usr/bin/python3 tests/blender/roundtrip.py --blender blender --brume build/brume NAME [options]
#
# Options: --workdir DIR (default: a temporary directory, removed), --width/--height/--samples/
# --bounces (scene settings, default 64x48, 128 spp, 3 bounces), --threads N (both renderers,
# default 1), --block B (z-test blocks, default 8). Exit status 0 if the images agree.
# Runs with Debian's python3 (numpy, OpenImageIO).
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import compare  # noqa: E402

EXPORTER = os.path.join(ROOT, "src", "blender", "brume_export.py")


def run(cmd, what, log):
    t0 = time.monotonic()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    dt = time.monotonic() - t0
    with open(log, "w") as f:
        f.write(p.stdout + "\n--- stderr ---\n" + p.stderr)
    if p.returncode != 0:
        sys.stderr.write(p.stdout[-3000:] + p.stderr[-3000:])
        raise SystemExit("roundtrip: %s failed (exit %d), log in %s" % (what, p.returncode, log))
    return p, dt


def cycles_render(blender, blend, out, log, seed=None, samples=None, threads=None):
    expr = ["import bpy", "s = bpy.context.scene", "s.render.filepath = %r" % out]
    if seed is not None:
        expr.append("s.cycles.seed = %d" % seed)
    if samples is not None:
        expr.append("s.cycles.samples = %d" % samples)
    if threads is not None:
        expr.append("s.render.threads = %d" % threads)
    expr.append("bpy.ops.render.render(write_still=True)")
    return run([blender, "-b", blend, "--python-exit-code", "1", "--python-expr", "; ".join(expr)],
               "Cycles render of " + blend, log)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("name")
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--brume", required=True)
    ap.add_argument("--workdir")
    ap.add_argument("--width", type=int, default=64)
    ap.add_argument("--height", type=int, default=48)
    ap.add_argument("--samples", type=int, default=128)
    ap.add_argument("--bounces", type=int, default=3)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--block", type=int, default=8)
    a = ap.parse_args()

    tmp = None
    work = a.workdir
    if work is None:
        tmp = tempfile.mkdtemp(prefix="brume-blender-")
        work = tmp
    os.makedirs(work, exist_ok=True)
    try:
        n = a.name
        blend = os.path.join(work, n + ".blend")
        gltf = os.path.join(work, n + ".gltf")
        run([a.blender, "-b", "--factory-startup", "--python-exit-code", "1", "-P", os.path.join(HERE, "make_scenes.py"),
             "--", work, "--width", str(a.width), "--height", str(a.height), "--samples", str(a.samples),
             "--bounces", str(a.bounces), "--threads", str(a.threads), n], "scene build", os.path.join(work, n + ".make.log"))
        p, _ = run([a.blender, "-b", blend, "--python-exit-code", "1", "-P", EXPORTER, "--", gltf], "export",
                   os.path.join(work, n + ".export.log"))
        warnings = [l for l in p.stderr.splitlines() if l.startswith("brume_export: warning")]
        for w in warnings:
            print(w)
        cy = os.path.join(work, n + ".cycles.exr")
        _, t_cycles = cycles_render(a.blender, blend, cy, os.path.join(work, n + ".cycles.log"))
        br = os.path.join(work, n + ".brume.exr")
        p, t_brume = run([a.brume, "render", gltf, "-o", br, "--threads", str(a.threads)], "brume render",
                         os.path.join(work, n + ".brume.log"))
        print(p.stdout.strip())
        r = compare.compare(compare.load_exr(cy), compare.load_exr(br), block=a.block)
        print(compare.format_result(n, r))
        print("%s: Cycles %.1f s (with Blender's start), brume %.1f s" % (n, t_cycles, t_brume))
        if not r["ok"]:
            print("%s: FAIL (images in %s)" % (n, work if tmp is None else "a removed temporary directory; use --workdir"))
            return 1
        print("%s: ok" % n)
        return 0
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
