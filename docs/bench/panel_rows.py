#!/usr/bin/python3
"""Per-row relative variance under a ceiling panel (docs/results.md, "Area lights close up").

Renders SCENE K times with different seeds at equal time (or equal spp) and reports, for each
method, the per-pixel relative variance var/mean^2 (over the K images) averaged over the rows
nearest the panel and over the rows far from it, their ratio, and the whole image's mean
relative variance times seconds, and the near rows' (lower is better: 1/efficiency).

  /usr/bin/python3 docs/bench/panel_rows.py --brume build/brume --scene scenes/bench_panel.gltf \
      --res 48x32 --near 0:4 --far 8:32 --time 4 --k 12 -- "pt --connect mis" "pt --connect mis --emitter-sampling area"
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio


def read(path):
    img = oiio.ImageBuf(path)
    return img.get_pixels(oiio.FLOAT)[:, :, :3].astype(np.float64)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--brume", default="build/brume")
    ap.add_argument("--scene", required=True)
    ap.add_argument("--res", default="48x32")
    ap.add_argument("--near", default="0:4", help="rows next to the panel, first:end")
    ap.add_argument("--far", default="8:32", help="rows far from it, first:end")
    ap.add_argument("--time", type=float, default=0, help="seconds per render (equal time)")
    ap.add_argument("--spp", type=int, default=0, help="spp per render (instead of --time)")
    ap.add_argument("--k", type=int, default=12, help="renders per method (seeds 1..k)")
    ap.add_argument("--max-depth", default="1")
    ap.add_argument("--threads", default="2")
    ap.add_argument("methods", nargs="+", help='integrator arguments, e.g. "pt --connect mis"')
    a = ap.parse_args()
    n0, n1 = (int(v) for v in a.near.split(":"))
    f0, f1 = (int(v) for v in a.far.split(":"))
    print(f"{'method':48s} {'spp':>6s} {'seconds':>8s} {'relvar near':>12s} {'relvar far':>11s} "
          f"{'near/far':>8s} {'relvar*s':>10s} {'near*s':>10s}")
    with tempfile.TemporaryDirectory() as tmp:
        for method in a.methods:
            imgs, secs, spps = [], [], []
            for seed in range(1, a.k + 1):
                out = os.path.join(tmp, f"r{seed}.exr")
                cmd = [a.brume, "render", a.scene, "-o", out, "--res", a.res, "--seed", str(seed),
                       "--max-depth", a.max_depth, "--threads", a.threads, "--integrator"] + method.split()
                cmd += ["--time", str(a.time)] if a.time > 0 else ["--spp", str(a.spp)]
                r = subprocess.run(cmd, capture_output=True, text=True)
                if r.returncode != 0:
                    sys.exit(f"{' '.join(cmd)}: {r.stderr.strip()}")
                words = r.stdout.split("\n")[0].split()
                spps.append(int(words[2]))  # "OUT: WxH, N spp, S s, ..."
                secs.append(float(words[4]))
                imgs.append(read(out))
            stack = np.stack(imgs)
            mean = stack.mean(axis=0)
            var = stack.var(axis=0, ddof=1)
            rel = (var / np.maximum(mean * mean, 1e-12)).mean(axis=2)  # per pixel, channels averaged
            near, far = rel[n0:n1].mean(), rel[f0:f1].mean()
            t = float(np.mean(secs))
            print(f"{method:48s} {int(np.mean(spps)):6d} {t:8.2f} {near:12.4g} {far:11.4g} {near / far:8.2f} "
                  f"{rel.mean() * t:10.4g} {near * t:10.4g}")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
