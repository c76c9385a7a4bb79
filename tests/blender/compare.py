# Image comparison of the round-trip tests: Cycles' EXR against brume's, both noisy estimates
# of the same image. Runs with Debian's /usr/bin/python3 (numpy, OpenImageIO); no bpy.
#
# The difference image D = cycles - brume has mean 0 in every pixel if both renderers agree.
# Pixel noise is independent from pixel to pixel (each renderer scrambles its numbers per
# pixel), so
#   - per channel, the image means agree if |mean(D)| <= max(rel_tol * |mean(cycles)|, 3 se),
#     se the standard error of mean(D) from the pixel variance of D pooled within blocks of
#     B x B pixels;
#   - per block of B x B pixels and channel, z = mean_block(D) / (std_block(D) / B), and the
#     worst |z| must stay under the Bonferroni bound for 1e-3 family-wise: the |z| all of that
#     many standard normals stay under with probability 0.999 (as tests/support/pixel_estimates.h
#     zBound does for the oracle tests).
# A comparison whose noise (3 se) exceeds 5 % of the mean fails as well: it could not tell a
# real 5 % difference apart.
import math

import numpy as np


def load_exr(path):
    import OpenImageIO as oiio
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise RuntimeError("%s: %s" % (path, buf.geterror()))
    px = buf.get_pixels(oiio.FLOAT)
    return np.asarray(px, dtype=np.float64)[:, :, :3]


def z_bound(comparisons, alpha=1e-3):
    target = alpha / max(1, comparisons)
    lo, hi = 0.0, 10.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if math.erfc(mid / math.sqrt(2.0)) > target:
            lo = mid
        else:
            hi = mid
    return hi


def blocks(img, b):
    h, w = img.shape[0] // b * b, img.shape[1] // b * b
    x = img[:h, :w]
    return x.reshape(h // b, b, w // b, b, -1).transpose(0, 2, 1, 3, 4).reshape(h // b, w // b, b * b, -1)


def compare(cycles, brume, block=8, rel_tol=0.02, alpha=1e-3, max_noise=0.05):
    """Returns a dict of the numbers and 'ok'."""
    if cycles.shape != brume.shape:
        raise ValueError("image sizes differ: %s and %s" % (cycles.shape, brume.shape))
    d = cycles - brume
    bl = blocks(d, block)                       # (by, bx, n, 3)
    n = bl.shape[2]
    bmean = bl.mean(axis=2)                     # (by, bx, 3)
    nblocks = bmean.shape[0] * bmean.shape[1]
    res = {"mean_cycles": cycles.reshape(-1, 3).mean(axis=0).tolist(),
           "mean_brume": brume.reshape(-1, 3).mean(axis=0).tolist(), "channels": []}
    ok = True
    for c in range(3):
        mc, mb = res["mean_cycles"][c], res["mean_brume"][c]
        # pixel variance pooled within blocks (a systematic difference between the images, which
        # varies over the image, does not inflate it as the spread of block means would)
        se = math.sqrt(float(np.mean(bl[:, :, :, c].var(axis=2, ddof=1))) / (n * nblocks))
        # (means over the cropped blocks and over the whole image differ only at the edge)
        diff = mc - mb
        tol = max(rel_tol * abs(mc), 3 * se)
        # A test too noisy to tell 5 % apart proves nothing: it fails too.
        chan_ok = abs(diff) <= tol and 3 * se <= max_noise * abs(mc)
        ok = ok and chan_ok
        res["channels"].append({"cycles": mc, "brume": mb, "rel": diff / mc if mc else float("inf"),
                                "se": se, "tol": tol, "ok": chan_ok})
    sd = bl.std(axis=2, ddof=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(sd > 0, bmean / (sd / math.sqrt(n)), np.where(np.abs(bmean) > 1e-6, np.inf, 0.0))
    bound = z_bound(nblocks * 3, alpha)
    worst = float(np.max(np.abs(z)))
    where = np.unravel_index(int(np.argmax(np.abs(z))), z.shape)
    res.update({"worst_z": worst, "z_bound": bound, "worst_block": [int(where[1]), int(where[0]), int(where[2])],
                "blocks": nblocks, "block": block, "z_ok": worst <= bound})
    res["ok"] = ok and res["z_ok"]
    return res


def format_result(name, r):
    lines = []
    for c, ch in zip("RGB", r["channels"]):
        lines.append("%s %s: cycles %.5f brume %.5f rel %+.2f%% (tol %.5f, se %.5f) %s"
                     % (name, c, ch["cycles"], ch["brume"], 100 * ch["rel"], ch["tol"], ch["se"],
                        "ok" if ch["ok"] else "FAIL"))
    lines.append("%s: worst block |z| %.2f at block (%d,%d) channel %d, bound %.2f over %d blocks x 3 channels %s"
                 % (name, r["worst_z"], r["worst_block"][0], r["worst_block"][1], r["worst_block"][2], r["z_bound"],
                    r["blocks"], "ok" if r["z_ok"] else "FAIL"))
    return "\n".join(lines)
