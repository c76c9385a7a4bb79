#!/usr/bin/python3
"""Charts and an HTML report for `brume bench` output directories.

    /usr/bin/python3 docs/bench/plot_bench.py DIR [DIR ...] [--reference FILE]

For each DIR written by `brume bench SCENE --out DIR` this reads DIR/results.csv and writes

  DIR/chart.png, DIR/chart.svg  relative MSE against render seconds, log-log, one line per
                                method (the dotted grey line is the 1/t slope of an unbiased
                                Monte Carlo estimator), titled with the scene's name;
  DIR/report.html               the chart, the results table, and side by side for each
                                method its image at the largest budget (DIR/<method>.exr,
                                equal time) sRGB-encoded, with a false-colour map of the
                                relative error |x - r| / (r + 0.01) (mean over RGB) against
                                the reference r, on one colour scale shared by all methods.

The reference is DIR/reference.exr (cached by bench when it renders one), or --reference FILE
(.exr or .pfm; use it when bench was run with --reference). EXR images are read with
OpenImageIO's Python module (Debian: python3-openimageio); without it the report says so and
leaves the images out (a .pfm reference is still read). Needs numpy and matplotlib (Debian:
python3-numpy, python3-matplotlib). Exit status 1 if some DIR could not be processed.
"""

import argparse
import base64
import csv
import html
import io
import os
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter  # noqa: E402

try:
    import OpenImageIO as oiio  # noqa: E402
except ImportError:  # images are optional
    oiio = None

REL_EPS = 0.01  # as in bench's rel_mse = mean (x - r)^2 / (r^2 + 0.01), here |x - r| / (r + 0.01)


class BenchError(Exception):
    pass


# ---------------------------------------------------------------------------------------------
# Reading

def read_results(path):
    """results.csv -> (scenes, {method: [row, ...] sorted by seconds}), methods in file order."""
    numeric = ("budget_s", "seconds", "spp", "rel_mse", "rmse", "efficiency")
    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            missing = [c for c in ("scene", "method") + numeric if c not in (reader.fieldnames or [])]
            if missing:
                raise BenchError("%s: missing column(s) %s" % (path, ", ".join(missing)))
            rows = list(reader)
    except OSError as e:
        raise BenchError("%s: %s" % (path, e.strerror or e))
    if not rows:
        raise BenchError("%s: no results" % path)
    methods, scenes = {}, []
    for line, row in enumerate(rows, start=2):
        try:
            values = {k: float(row[k]) for k in numeric}
        except (TypeError, ValueError):
            raise BenchError("%s:%d: not a number in %r" % (path, line, row))
        values["scene"], values["method"] = row["scene"], row["method"]
        methods.setdefault(row["method"], []).append(values)
        if row["scene"] not in scenes:
            scenes.append(row["scene"])
    for rows_of_method in methods.values():
        rows_of_method.sort(key=lambda r: (r["budget_s"], r["seconds"]))
    return scenes, methods


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        if kind not in (b"PF", b"Pf"):
            raise BenchError("%s: not a PFM file" % path)
        dims = f.readline().split()
        while not dims:
            dims = f.readline().split()
        width, height = int(dims[0]), int(dims[1])
        scale = float(f.readline().strip())
        channels = 3 if kind == b"PF" else 1
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    if data.size != width * height * channels:
        raise BenchError("%s: truncated PFM" % path)
    image = data.reshape(height, width, channels)[::-1]  # PFM rows run bottom to top
    if channels == 1:
        image = np.repeat(image, 3, axis=2)
    return np.ascontiguousarray(image, dtype=np.float64)


def read_image(path):
    """Linear RGB float image (height, width, 3)."""
    if path.lower().endswith(".pfm"):
        return read_pfm(path)
    if oiio is None:
        raise BenchError("%s: cannot read EXR images without OpenImageIO's Python module "
                         "(Debian: python3-openimageio)" % path)
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise BenchError("%s: %s" % (path, buf.geterror()))
    pixels = np.asarray(buf.get_pixels(oiio.FLOAT), dtype=np.float64)
    if pixels.ndim == 2:
        pixels = pixels[:, :, None]
    if pixels.shape[2] == 1:
        pixels = np.repeat(pixels, 3, axis=2)
    return pixels[:, :, :3]


def srgb(linear):
    """Clamp to [0, 1] and encode with the sRGB curve (as brume's PNG output does)."""
    x = np.clip(np.nan_to_num(linear, nan=0.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)


def relative_error(image, reference):
    return np.mean(np.abs(image - reference) / (reference + REL_EPS), axis=2)


def method_stem(method):
    return method.replace(":", "_")


# ---------------------------------------------------------------------------------------------
# Figures

def log_ticks(lo, hi):
    """Tick values m * 10^k in [lo, hi] from the sparsest mantissa set that gives at least three
    ticks and leaves no gap (edges included) wider than half the axis, on a log scale."""
    span = np.log10(hi / lo)
    ticks = []
    for mantissas in ((1,), (1, 2, 5), (1, 2, 3, 4, 5, 6, 7, 8, 9),
                      (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 7, 8, 9)):
        ticks = [float("%.12g" % (m * 10.0 ** k))
                 for k in range(int(np.floor(np.log10(lo))) - 1, int(np.ceil(np.log10(hi))) + 1)
                 for m in mantissas if lo <= m * 10.0 ** k <= hi]
        edges = np.log10([lo] + ticks + [hi])
        if len(ticks) >= 3 and np.max(np.diff(edges)) <= 0.5 * span:
            break
    return ticks


def save_chart(directory, scenes, methods):
    fig, ax = plt.subplots(figsize=(7.6, 4.4))
    all_t, all_e = [], []
    for method, rows in methods.items():
        pts = [(r["seconds"], r["rel_mse"]) for r in rows if r["seconds"] > 0 and r["rel_mse"] > 0]
        if not pts:
            continue
        t, e = zip(*pts)
        ax.plot(t, e, marker="o", linewidth=1.6, label=method)
        all_t += t
        all_e += e
    if not all_t:
        plt.close(fig)
        raise BenchError("%s: no positive (seconds, rel_mse) pairs to plot" % directory)
    # 1/t guide through the geometric mean of the points
    t0, t1 = min(all_t), max(all_t)
    if t1 > t0:
        tc = np.exp(np.mean(np.log(all_t)))
        ec = np.exp(np.mean(np.log(all_e)))
        ts = np.array([t0, t1])
        ax.plot(ts, ec * tc / ts, linestyle=":", color="0.55", linewidth=1.2, label="∝ 1/t")
    ax.set_xscale("log")
    ax.set_yscale("log")
    # labelled ticks at 1, 2, 5 (or 1..9) times powers of ten, written as plain numbers
    plain = FuncFormatter(lambda v, _pos: "%g" % v)
    for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        axis.set_major_locator(FixedLocator(log_ticks(lo, hi)))
        axis.set_major_formatter(plain)
        axis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("render time (s)")
    ax.set_ylabel("relative MSE")
    ax.set_title(", ".join(scenes))
    ax.grid(True, which="both", linewidth=0.4, alpha=0.5)
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "chart.png"), dpi=120)
    fig.savefig(os.path.join(directory, "chart.svg"), metadata={"Date": None})
    plt.close(fig)


def image_panel(methods, images, reference):
    """One figure: per method (and the reference) its sRGB image on top and, below, its
    relative-error map on a shared colour scale. Returns PNG bytes."""
    names = list(images)
    columns = len(names) + (1 if reference is not None else 0)
    h, w = next(iter(images.values())).shape[:2]
    panel_w = 3.0
    rows = 2 if reference is not None else 1
    fig, axes = plt.subplots(rows, columns, squeeze=False,
                             figsize=(panel_w * columns + 0.9, (panel_w * h / w + 0.55) * rows))
    errors = {}
    if reference is not None:
        errors = {m: relative_error(images[m], reference) for m in names}
        stacked = np.concatenate([e.ravel() for e in errors.values()])
        vmax = float(np.percentile(stacked, 99.0)) if stacked.size else 1.0
        vmax = vmax if vmax > 0 else 1.0
    mapped = None
    for k, m in enumerate(names):
        last = methods[m][-1]
        ax = axes[0][k]
        ax.imshow(srgb(images[m]), interpolation="nearest")
        ax.set_title("%s\n%.2f s, %d spp" % (m, last["seconds"], int(last["spp"])), fontsize=9)
        if reference is not None:
            ax = axes[1][k]
            mapped = ax.imshow(errors[m], cmap="inferno", vmin=0.0, vmax=vmax, interpolation="nearest")
            ax.set_title("relative error, mean %.3g" % float(np.mean(errors[m])), fontsize=9)
    for row in axes:
        for ax in row:
            ax.set_xticks([])
            ax.set_yticks([])
    if reference is not None:
        ax = axes[0][columns - 1]
        ax.imshow(srgb(reference), interpolation="nearest")
        ax.set_title("reference", fontsize=9)
        # the colour bar goes in the free slot under the reference
        slot = axes[1][columns - 1]
        slot.axis("off")
        cax = slot.inset_axes([0.04, 0.0, 0.08, 1.0])
        bar = fig.colorbar(mapped, cax=cax)
        bar.set_label("|x − r| / (r + 0.01)", fontsize=9)
        bar.ax.tick_params(labelsize=8)
    fig.tight_layout()
    out = io.BytesIO()
    fig.savefig(out, format="png", dpi=110)
    plt.close(fig)
    return out.getvalue()


# ---------------------------------------------------------------------------------------------
# The report

def results_table(methods):
    head = ("method", "budget (s)", "seconds", "spp", "rel. MSE", "RMSE", "efficiency")
    lines = ["<table>", "<tr>" + "".join("<th>%s</th>" % h for h in head) + "</tr>"]
    for method, rows in methods.items():
        for r in rows:
            cells = (html.escape(method), "%g" % r["budget_s"], "%.3f" % r["seconds"], "%d" % r["spp"],
                     "%.4g" % r["rel_mse"], "%.4g" % r["rmse"], "%.4g" % r["efficiency"])
            lines.append("<tr>" + "".join("<td>%s</td>" % c for c in cells) + "</tr>")
    lines.append("</table>")
    return "\n".join(lines)


def load_images(directory, methods, reference_arg):
    """({method: image}, reference or None, [notes])."""
    notes, images = [], {}
    ref_path = reference_arg or os.path.join(directory, "reference.exr")
    reference = None
    if oiio is None:
        notes.append("OpenImageIO's Python module is not installed (Debian: python3-openimageio), "
                     "so the EXR images are left out.")
        if not ref_path.lower().endswith(".pfm"):
            return images, reference, notes
    if not os.path.exists(ref_path):
        notes.append("No reference image (%s): bench was run with --reference; pass the same file "
                     "to this script with --reference to get error maps." % html.escape(ref_path))
    else:
        try:
            reference = read_image(ref_path)
        except BenchError as e:
            notes.append(html.escape(str(e)))
    for method in methods:
        path = os.path.join(directory, method_stem(method) + ".exr")
        if not os.path.exists(path):
            notes.append("%s: no image (%s)." % (html.escape(method), html.escape(path)))
            continue
        if oiio is None:
            break
        try:
            images[method] = read_image(path)
        except BenchError as e:
            notes.append(html.escape(str(e)))
    if reference is not None:
        for method in list(images):
            if images[method].shape != reference.shape:
                notes.append("%s: image size %s differs from the reference's %s; left out." %
                             (html.escape(method), images[method].shape[1::-1], reference.shape[1::-1]))
                del images[method]
    return images, reference, notes


def write_report(directory, scenes, methods, reference_arg):
    images, reference, notes = load_images(directory, methods, reference_arg)
    title = "brume bench: " + ", ".join(scenes)
    parts = ["<!DOCTYPE html>", "<html><head><meta charset=\"utf-8\">",
             "<title>%s</title>" % html.escape(title),
             "<style>body{font-family:sans-serif;margin:1.5em;max-width:80em}"
             "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:2px 8px;"
             "text-align:right}th{background:#eee}td:first-child{text-align:left}"
             ".note{color:#a40}img{max-width:100%}</style></head><body>",
             "<h1>%s</h1>" % html.escape(title),
             "<p><img src=\"chart.svg\" alt=\"relative MSE against render time\" width=\"760\"></p>",
             "<h2>Results</h2>", results_table(methods),
             "<p>rel. MSE = mean over pixels and channels of (x − r)² / (r² + 0.01); "
             "efficiency = 1 / (rel. MSE × seconds).</p>",
             "<h2>Images at equal time</h2>"]
    largest = max(r["budget_s"] for rows in methods.values() for r in rows)
    if images:
        png = image_panel(methods, images, reference)
        what = "sRGB-encoded and clamped to [0, 1]"
        if reference is not None:
            what += ("; below it, the relative error |x − r| / (r + 0.01), mean over RGB, on one "
                     "colour scale (0 to the 99th percentile of all maps)")
        parts.append("<p>Each method's image at the largest budget (%g s), %s.</p>" % (largest, what))
        parts.append("<p><img alt=\"images and relative errors\" src=\"data:image/png;base64,%s\"></p>"
                     % base64.b64encode(png).decode("ascii"))
    for note in notes:
        parts.append("<p class=\"note\">%s</p>" % note)
    if not images and not notes:
        parts.append("<p class=\"note\">No images.</p>")
    parts.append("</body></html>")
    with open(os.path.join(directory, "report.html"), "w", encoding="utf-8") as f:
        f.write("\n".join(parts) + "\n")
    return len(images), reference is not None, notes


def main(argv=None):
    parser = argparse.ArgumentParser(description="Charts and an HTML report for brume bench output.")
    parser.add_argument("dirs", nargs="+", metavar="DIR", help="a directory written by brume bench --out")
    parser.add_argument("--reference", metavar="FILE",
                        help="reference image (.exr or .pfm) when DIR has no reference.exr")
    args = parser.parse_args(argv)
    status = 0
    for directory in args.dirs:
        try:
            scenes, methods = read_results(os.path.join(directory, "results.csv"))
            save_chart(directory, scenes, methods)
            n, with_ref, notes = write_report(directory, scenes, methods, args.reference)
            print("%s: chart.png, chart.svg, report.html (%d image%s%s)" %
                  (directory, n, "" if n == 1 else "s", ", error maps" if with_ref and n else ""))
            for note in notes:
                print("  note: " + html.unescape(note))
        except BenchError as e:
            print("plot_bench: error: %s" % e, file=sys.stderr)
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
