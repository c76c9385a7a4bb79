# The Blender gallery of docs/blender.md: every round-trip scene rendered by Cycles and, after
# export, by brume in the same time, side by side (docs/gallery/blender_<scene>.png, Cycles
# left, brume right), with each one's RMSE against a long Cycles render (the reference).
#
#   /usr/bin/python3 docs/bench/blender_gallery.py --brume build/brume [--width 128 --height 96
#       --samples 64 --reference-samples 1024 --threads 1] [SCENE ...]
#
# Cycles renders SAMPLES spp and its render time (Blender's own "Time:" line, without start-up
# and scene loading) is brume's --time budget. Prints a Markdown table. Minutes, not seconds:
# not part of the tests.
import argparse
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "blender"))
import compare  # noqa: E402
import roundtrip  # noqa: E402

SCENES = ["fog_point", "spot_cube", "sun_window", "area_fog", "glass_fog"]


def render_seconds(log):
    text = open(log).read()
    m = re.findall(r"Time: (\d+):(\d+\.\d+)", text)
    if not m:
        raise SystemExit("no render time in " + log)
    mins, secs = m[-1]
    return 60 * int(mins) + float(secs)


def to_png(img, path):
    import OpenImageIO as oiio
    x = np.clip(img, 0, None)
    srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    out = (np.clip(srgb, 0, 1) * 255 + 0.5).astype(np.uint8)
    spec = oiio.ImageSpec(out.shape[1], out.shape[0], 3, oiio.UINT8)
    o = oiio.ImageOutput.create(path)
    o.open(path, spec)
    o.write_image(out)
    o.close()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--brume", required=True)
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--height", type=int, default=96)
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--reference-samples", type=int, default=1024)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--workdir")
    a = ap.parse_args()
    work = a.workdir or tempfile.mkdtemp(prefix="brume-blender-gallery-")
    os.makedirs(work, exist_ok=True)
    rows = []
    for n in a.scenes or SCENES:
        blend, gltf = os.path.join(work, n + ".blend"), os.path.join(work, n + ".gltf")
        roundtrip.run([a.blender, "-b", "--factory-startup", "--python-exit-code", "1", "-P",
                       os.path.join(ROOT, "tests", "blender", "make_scenes.py"), "--", work, "--width", str(a.width),
                       "--height", str(a.height), "--samples", str(a.samples), "--threads", str(a.threads), n],
                      "scene build", os.path.join(work, n + ".make.log"))
        roundtrip.run([a.blender, "-b", blend, "--python-exit-code", "1", "-P", roundtrip.EXPORTER, "--", gltf],
                      "export", os.path.join(work, n + ".export.log"))
        ref = os.path.join(work, n + ".reference.exr")
        roundtrip.cycles_render(a.blender, blend, ref, os.path.join(work, n + ".reference.log"), seed=7,
                                samples=a.reference_samples)
        cy = os.path.join(work, n + ".cycles.exr")
        roundtrip.cycles_render(a.blender, blend, cy, os.path.join(work, n + ".cycles.log"))
        t = render_seconds(os.path.join(work, n + ".cycles.log"))
        br = os.path.join(work, n + ".brume.exr")
        p, _ = roundtrip.run([a.brume, "render", gltf, "-o", br, "--threads", str(a.threads), "--time", "%.3f" % t],
                             "brume render", os.path.join(work, n + ".brume.log"))
        spp_brume = int(re.search(r", (\d+) spp", p.stdout).group(1))
        R, C, B = compare.load_exr(ref), compare.load_exr(cy), compare.load_exr(br)
        rmse_c = float(np.sqrt(np.mean((C - R) ** 2)))
        rmse_b = float(np.sqrt(np.mean((B - R) ** 2)))
        to_png(np.concatenate([C, np.zeros((C.shape[0], 4, 3)), B], axis=1),
               os.path.join(ROOT, "docs", "gallery", "blender_%s.png" % n))
        mc, mb, mr = C.mean(), B.mean(), R.mean()
        rows.append("| `%s` | %.2f s | %d | %d | %.4f | %.4f | %.3f | %+.2f%% |" % (
            n, t, a.samples, spp_brume, rmse_c, rmse_b, rmse_b / rmse_c, 100 * (mb - mr) / mr))
        print(rows[-1], flush=True)
    print("| scene | time | Cycles spp | brume spp | RMSE Cycles | RMSE brume | brume / Cycles | brume mean vs reference |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
