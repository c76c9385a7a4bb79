# Bad input for the exporter:
#   - a volume made of Volume Scatter + a Transparent BSDF (which has no brume equivalent) exports
#     with a warning naming the material and the node, and the medium is still there (from the
#     part that maps), bounding its mesh, and brume loads and renders the file;
#   - an output directory that does not exist is an error: non-zero exit, one line on stderr;
#   - a command line without an output file is a usage error.
#
#   /usr/bin/python3 tests/blender/bad_input.py --blender blender --brume build/brume
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
EXPORTER = os.path.join(os.path.dirname(os.path.dirname(HERE)), "src", "blender", "brume_export.py")

failures = []


def check(cond, what):
    print(("ok: " if cond else "FAIL: ") + what)
    if not cond:
        failures.append(what)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--brume", required=True)
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="brume-blender-bad-")
    try:
        subprocess.run([a.blender, "-b", "--factory-startup", "--python-exit-code", "1", "-P",
                        os.path.join(HERE, "make_scenes.py"), "--", work, "bad_volume"],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        blend = os.path.join(work, "bad_volume.blend")
        out = os.path.join(work, "bad.gltf")
        p = subprocess.run([a.blender, "-b", blend, "-P", EXPORTER, "--", out], capture_output=True, text=True)
        warnings = [l for l in p.stderr.splitlines() if l.startswith("brume_export: warning:")]
        for w in warnings:
            print("  " + w)
        check(p.returncode == 0, "the scene with an unsupported volume node exports (exit %d)" % p.returncode)
        check(any("material 'odd_fog'" in w and "'Odd'" in w for w in warnings),
              "a warning names the material 'odd_fog' and the node 'Odd'")
        g = json.load(open(out))
        media = g.get("extensions", {}).get("BRUME_media", {}).get("media", [])
        check(len(media) == 1 and media[0]["name"] == "odd_fog", "the medium is exported (%s)" % media)
        check(bool(media) and abs(media[0].get("scattering", 0) - 0.4) < 1e-6,
              "with the Volume Scatter's sigma_s = 0.8 (its colour) x 0.5 (its density)")
        boxes = [m for m in g["meshes"] if m.get("extensions", {}).get("BRUME_media", {}).get("interior") == 0]
        check(len(boxes) == 1 and all("material" not in pr for pr in boxes[0]["primitives"]),
              "the cube bounds it, as an invisible boundary")
        r = subprocess.run([a.brume, "render", out, "-o", os.path.join(work, "bad.pfm"), "--res", "16x12", "--spp", "2",
                            "--threads", "1"], capture_output=True, text=True)
        check(r.returncode == 0, "brume renders the export (%s)" % r.stderr.strip())

        missing = os.path.join(work, "no", "such", "dir", "x.gltf")
        p = subprocess.run([a.blender, "-b", blend, "-P", EXPORTER, "--", missing], capture_output=True, text=True)
        errors = [l for l in p.stderr.splitlines() if l.startswith("brume_export: error:")]
        check(p.returncode != 0, "a missing output directory: exit %d" % p.returncode)
        check(len(errors) == 1 and "does not exist" in errors[0], "one error line: %s" % errors)
        check(not os.path.exists(os.path.dirname(missing)), "nothing created")

        p = subprocess.run([a.blender, "-b", blend, "-P", EXPORTER], capture_output=True, text=True)
        check(p.returncode == 2 and "usage:" in p.stderr, "no output file: usage error, exit %d" % p.returncode)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if failures:
        print("%d check(s) failed" % len(failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
