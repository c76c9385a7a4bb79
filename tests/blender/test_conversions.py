# Unit tests of the exporter's conversion formulas (src/blender/brume_export.py), against
# numbers measured in Cycles 3.4 by measure_cycles.py (kept in cycles_measurements.json).
# Runs with any python3 that has numpy (Debian's /usr/bin/python3, or Blender's own):
#
#   /usr/bin/python3 tests/blender/test_conversions.py [-v]
#   /usr/bin/python3 tests/blender/test_conversions.py --measurements NEW.json   (re-measured numbers)
import json
import math
import os
import sys
import unittest

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(HERE)), "src", "blender"))
import brume_export as bx  # noqa: E402

MEASUREMENTS = os.path.join(HERE, "cycles_measurements.json")


def load():
    with open(MEASUREMENTS) as f:
        return json.load(f)


def pixel_grid(n, h):
    xs = (np.arange(n) + 0.5) / n * 2 - 1
    X, Y = np.meshgrid(xs, -xs)
    return X, Y, np.sqrt(X * X + Y * Y + h * h)


def area_irradiance(radiance, outline, h, X, Y, samples=120):
    """Irradiance at the plane's points (X, Y, 0) from a Lambertian polygon of the given radiance
    at height h facing down (numerical integration over a fine grid of the bounding box)."""
    xs = [p[0] for p in outline]
    ys = [p[1] for p in outline]
    gx = np.linspace(min(xs), max(xs), samples + 1)
    gy = np.linspace(min(ys), max(ys), samples + 1)
    cx, cy = 0.5 * (gx[1:] + gx[:-1]), 0.5 * (gy[1:] + gy[:-1])
    SX, SY = np.meshgrid(cx, cy)
    inside = np.ones_like(SX, dtype=bool)
    # convex polygon, counter-clockwise
    for i in range(len(outline)):
        (x0, y0), (x1, y1) = outline[i], outline[(i + 1) % len(outline)]
        inside &= (x1 - x0) * (SY - y0) - (y1 - y0) * (SX - x0) >= 0
    dA = (gx[1] - gx[0]) * (gy[1] - gy[0])
    sx, sy = SX[inside], SY[inside]
    E = np.zeros_like(X)
    for idx in np.ndindex(X.shape):
        dd = (sx - X[idx]) ** 2 + (sy - Y[idx]) ** 2 + h * h
        E[idx] = radiance * np.sum(h * h / dd ** 2) * dA
    return E


class Lights(unittest.TestCase):
    m = load()

    def test_point_watts_to_w_per_sr(self):
        d = self.m["point"]
        E = np.array(d["irradiance"])
        X, Y, dist = pixel_grid(E.shape[0], d["height"])
        predicted = bx.point_intensity(d["power"]) * d["height"] / dist ** 3
        self.assertAlmostEqual(bx.point_intensity(4 * math.pi), 1.0)
        self.assertLess(abs((E / predicted).mean() - 1), 0.005)
        self.assertLess(np.max(np.abs(E / predicted - 1)), 0.02)

    def test_spot_intensity_and_cycles_cos_factor(self):
        d = self.m["spot"]
        E = np.array(d["irradiance"])
        X, Y, dist = pixel_grid(E.shape[0], d["height"])
        cos = d["height"] / dist
        prof = np.vectorize(lambda c: bx.cycles_spot_profile(c, d["spot_size"], 0.0))(cos)
        predicted = bx.spot_intensity(d["power"]) * prof * d["height"] / dist ** 3
        self.assertLess(np.max(np.abs(E / predicted - 1)), 0.02)
        # Without the cos factor (brume's glTF spot) the corners are off by 1 - cos(theta):
        inner, outer = bx.spot_cones(d["spot_size"], 0.0)
        gl = np.vectorize(lambda c: bx.gltf_spot_profile(c, inner, outer))(cos)
        gltf_pred = bx.spot_intensity(d["power"]) * gl * d["height"] / dist ** 3
        err = np.max(np.abs(E / gltf_pred - 1))
        self.assertGreater(err, 0.1)  # the measurement can tell the two models apart
        self.assertLessEqual(err, bx.spot_cos_factor_error(d["spot_size"]) + 0.02)

    def test_spot_extras(self):
        self.assertEqual(bx.cycles_spot_extras(0.15), {"spotProfile": "cycles", "spotBlend": 0.15})
        self.assertEqual(bx.cycles_spot_extras(1.7)["spotBlend"], 1.0)
        # brume's C++ profile (tests/test_spot_profile.cpp) is this formula: its hand values.
        self.assertAlmostEqual(bx.cycles_spot_profile(0.876074, math.pi / 3, 0.15), 0.5 * 0.876074, places=4)
        self.assertAlmostEqual(bx.cycles_spot_profile(0.95, math.pi / 3, 0.15), 0.95)
        self.assertEqual(bx.cycles_spot_profile(0.866, math.pi / 3, 0.15), 0.0)

    def test_spot_blend_band(self):
        d = self.m["spot_blend"]
        E = np.array(d["irradiance"])
        X, Y, dist = pixel_grid(E.shape[0], d["height"])
        cos = d["height"] / dist
        prof = np.vectorize(lambda c: bx.cycles_spot_profile(c, d["spot_size"], d["spot_blend"]))(cos)
        predicted = bx.spot_intensity(d["power"]) * prof * d["height"] / dist ** 3
        # pixels average over their area where the profile changes fast: compare sums and a loose max
        self.assertLess(abs(E.sum() / predicted.sum() - 1), 0.03)
        lit = predicted > 0.2 * predicted.max()
        self.assertLess(np.max(np.abs(E[lit] / predicted[lit] - 1)), 0.15)

    def test_spot_cones(self):
        size, blend = math.radians(60), 0.5
        inner, outer = bx.spot_cones(size, blend)
        self.assertAlmostEqual(outer, size / 2)
        cos_o = math.cos(outer)
        self.assertAlmostEqual(math.cos(inner) - cos_o, (1 - cos_o) * blend)
        # same cut-off and same band as Cycles
        for c in (cos_o - 1e-3, cos_o + 1e-3, math.cos(inner) + 1e-3, 1.0):
            self.assertEqual(bx.cycles_spot_profile(c, size, blend) > 0, bx.gltf_spot_profile(c, inner, outer) > 0)
        self.assertAlmostEqual(bx.gltf_spot_profile(math.cos(inner) + 1e-9, inner, outer), 1.0, places=5)
        # blend 0: a valid glTF cone (inner < outer)
        i0, o0 = bx.spot_cones(math.radians(40), 0.0)
        self.assertLess(i0, o0)
        # wider than 180 degrees: cut at pi/2
        self.assertAlmostEqual(bx.spot_cones(math.radians(200), 0.1)[1], math.pi / 2)

    def test_sun_strength_is_irradiance(self):
        d = self.m["sun"]
        E = np.array(d["irradiance"])
        self.assertLess(abs(E.mean() / bx.sun_irradiance(d["strength"]) - 1), 1e-3)

    def check_area(self, key):
        d = self.m[key]
        E = np.array(d["irradiance"])
        X, Y, _ = pixel_grid(E.shape[0], d["height"])
        area = bx.area_light_area(d["shape"], d["size"], d["size_y"])
        outline = bx.area_light_outline(d["shape"], d["size"], d["size_y"])
        self.assertAlmostEqual(bx.polygon_area(outline), area, places=9)
        L = bx.area_radiance(d["power"], area)
        predicted = area_irradiance(L, outline, d["height"], X, Y)
        ratio = E.sum() / predicted.sum()
        self.assertLess(abs(ratio - 1), 0.01, "%s: Cycles / formula = %.4f" % (key, ratio))
        # P / (pi A), the Lambertian-power guess, is 4/pi off: the measurement rejects it
        self.assertGreater(abs(E.sum() / (predicted.sum() * 4 / math.pi) - 1), 0.15)

    def test_area_square(self):
        self.check_area("area_square")

    def test_area_rectangle(self):
        self.check_area("area_rectangle")

    def test_area_disk(self):
        self.check_area("area_disk")

    def test_area_ellipse(self):
        self.check_area("area_ellipse")

    def test_area_shapes(self):
        self.assertAlmostEqual(bx.area_light_area("SQUARE", 2, 7), 4)
        self.assertAlmostEqual(bx.area_light_area("RECTANGLE", 2, 3), 6)
        self.assertAlmostEqual(bx.area_light_area("DISK", 2, 7), math.pi)
        self.assertAlmostEqual(bx.area_light_area("ELLIPSE", 2, 4), 2 * math.pi)
        self.assertRaises(ValueError, bx.area_light_area, "TRIANGLE", 1, 1)

    def test_emission(self):
        d = self.m["emission"]
        r = bx.emission_radiance(d["color"], d["strength"])
        for a, b in zip(r, d["pixel"]):
            self.assertAlmostEqual(a, b, places=4)
        f, s = bx.emissive_factor_and_strength([5.0, 2.5, 1.0])
        self.assertEqual(f, [1.0, 0.5, 0.2])
        self.assertEqual(s, 5.0)
        self.assertEqual(bx.emissive_factor_and_strength([0.0, 0.0, 0.0]), ([0.0, 0.0, 0.0], 1.0))


class Volumes(unittest.TestCase):
    m = load()

    def medium_of(self, v):
        if v["node"] == "principled":
            return bx.principled_volume(v["color"], v["density"], v["absorption_color"], 0.0)
        if v["node"] == "scatter":
            return bx.volume_scatter(v["color"], v["density"], 0.0)
        return bx.volume_absorption(v["color"], v["density"])

    def test_extinction_against_cycles(self):
        for v in self.m["volumes"]:
            med = self.medium_of(v)
            for c in range(3):
                st = med["scattering"][c] + med["absorption"][c]
                self.assertLess(abs(st - v["extinction"][c]), 0.01,
                                "%s channel %d: formula %.4f, Cycles %.4f" % (v["node"], c, st, v["extinction"][c]))

    def test_principled_split(self):
        m = bx.principled_volume([0.5, 0.5, 0.5], 2.0, [0.0, 0.0, 0.0], 0.3)  # Blender's defaults, density 2
        self.assertEqual(m["scattering"], [1.0, 1.0, 1.0])
        self.assertEqual(m["absorption"], [1.0, 1.0, 1.0])
        self.assertEqual(m["anisotropy"], 0.3)
        m = bx.principled_volume([0.2, 1.0, 1.5], 1.0, [0.25, 0.25, 1.0], 0.0)
        self.assertAlmostEqual(m["absorption"][0], 0.8 * 0.5)
        self.assertEqual(m["absorption"][1], 0.0)
        self.assertEqual(m["absorption"][2], 0.0)
        self.assertEqual(m["scattering"][2], 1.5)
        self.assertEqual(bx.principled_volume([1, 1, 1], -3, [0, 0, 0], 0)["scattering"], [0, 0, 0])
        self.assertEqual(bx.principled_volume([1, 1, 1], 1, [0, 0, 0], 1.0)["anisotropy"], 0.999)

    def test_scatter_and_absorption(self):
        s = bx.volume_scatter([0.5, 0.25, 1.0], 2.0, -0.4)
        self.assertEqual(s["scattering"], [1.0, 0.5, 2.0])
        self.assertEqual(s["absorption"], [0.0, 0.0, 0.0])
        self.assertEqual(s["anisotropy"], -0.4)
        a = bx.volume_absorption([0.5, 0.25, 1.0], 2.0)
        self.assertEqual(a["absorption"], [1.0, 1.5, 0.0])
        self.assertEqual(a["scattering"], [0.0, 0.0, 0.0])

    def test_add_and_mix(self):
        s = bx.volume_scatter([1, 1, 1], 1.0, 0.6)
        t = bx.volume_scatter([1, 1, 1], 3.0, -0.2)
        a = bx.volume_absorption([0.5, 0.5, 0.5], 2.0)
        m, differ = bx.add_media(s, a)
        self.assertEqual(m["scattering"], [1, 1, 1])
        self.assertEqual(m["absorption"], [1.0, 1.0, 1.0])
        self.assertAlmostEqual(m["anisotropy"], 0.6)
        self.assertFalse(differ)
        m, differ = bx.add_media(s, t)
        self.assertTrue(differ)
        self.assertAlmostEqual(m["anisotropy"], (0.6 * 1 - 0.2 * 3) / 4)
        self.assertEqual(m["scattering"], [4, 4, 4])
        m, _ = bx.mix_media(s, a, 0.25)
        self.assertEqual(m["scattering"], [0.75, 0.75, 0.75])
        self.assertEqual(m["absorption"], [0.25, 0.25, 0.25])

    def test_emission(self):
        # Volume emission is colour x strength per metre, whatever the density; Add sums it,
        # Mix blends it, and the medium's JSON carries it only where it is not black.
        self.assertEqual(bx.volume_emission([1.0, 0.5, 0.0], 4.0), [4.0, 2.0, 0.0])
        self.assertEqual(bx.volume_emission([1.0, -1.0, 0.5], -2.0), [0.0, 0.0, 0.0])
        p = bx.principled_volume([0.5] * 3, 3.0, [0.0] * 3, 0.2, bx.volume_emission([1.0, 0.5, 0.25], 2.0))
        self.assertEqual(p["emission"], [2.0, 1.0, 0.5])
        glow = dict(bx.ZERO_MEDIUM, emission=bx.volume_emission([0.2, 0.3, 1.0], 0.5))
        m, differ = bx.add_media(p, glow)
        self.assertFalse(differ)
        self.assertEqual(m["emission"], [2.1, 1.15, 1.0])
        m, _ = bx.mix_media(p, glow, 0.5)
        self.assertEqual(m["emission"], [1.05, 0.575, 0.5])
        self.assertEqual(bx.medium_json("glow", m)["emission"], [1.05, 0.575, 0.5])
        self.assertNotIn("emission", bx.medium_json("fog", bx.volume_scatter([1, 1, 1], 1.0, 0.0)))


class _Sock:
    """A stand-in for a Blender node socket: a default value and an optional link."""

    def __init__(self, value=None, source=None):
        self.default_value = value
        self.is_linked = source is not None
        self.links = [type("Link", (), {"from_node": source})()] if source is not None else []


class _Node:
    """A stand-in for a Blender shader node: its type, inputs by name (and by position) and
    attributes."""

    def __init__(self, idname, inputs=(), **attrs):
        self.bl_idname = idname
        self.name = idname
        self._inputs = list(inputs)
        self.__dict__.update(attrs)

    @property
    def inputs(self):
        node = self

        class Inputs(list):
            def get(self, key):
                return dict(node._inputs).get(key)

        return Inputs(sock for _, sock in self._inputs)


class VolumeGrids(unittest.TestCase):
    """Which grid of a Volume object's .vdb its material reads as density (issue: the exporter
    always wrote "density")."""

    def test_principled_density_attribute(self):
        node = _Node("ShaderNodeVolumePrincipled", [("Density", _Sock(1.0)), ("Density Attribute", _Sock("smoke"))])
        self.assertEqual(bx.density_grid_of_node(node), "smoke")
        node = _Node("ShaderNodeVolumePrincipled", [("Density", _Sock(1.0)), ("Density Attribute", _Sock(""))])
        self.assertEqual(bx.density_grid_of_node(node), "density")

    def test_attribute_node_into_scatter_density(self):
        attr = _Node("ShaderNodeAttribute", attribute_name="heat_density")
        node = _Node("ShaderNodeVolumeScatter", [("Color", _Sock((1, 1, 1, 1))), ("Density", _Sock(1.0, attr))])
        self.assertEqual(bx.density_grid_of_node(node), "heat_density")
        info = _Node("ShaderNodeVolumeInfo")
        node = _Node("ShaderNodeVolumeAbsorption", [("Density", _Sock(1.0, info))])
        self.assertEqual(bx.density_grid_of_node(node), "density")
        self.assertIsNone(bx.density_grid_of_node(_Node("ShaderNodeVolumeScatter", [("Density", _Sock(1.0))])))

    def test_through_add_and_mix(self):
        attr = _Node("ShaderNodeAttribute", attribute_name="soot")
        scatter = _Node("ShaderNodeVolumeScatter", [("Density", _Sock(1.0, attr))])
        plain = _Node("ShaderNodeVolumeAbsorption", [("Density", _Sock(1.0))])
        add = _Node("ShaderNodeAddShader", [("Shader", _Sock(None, plain)), ("Shader_001", _Sock(None, scatter))])
        self.assertEqual(bx.density_grid_of_node(add), "soot")
        mix = _Node("ShaderNodeMixShader", [("Fac", _Sock(0.5)), ("Shader", _Sock(None, scatter)),
                                            ("Shader_001", _Sock(None, plain))])
        self.assertEqual(bx.density_grid_of_node(mix), "soot")


class Blackbody(unittest.TestCase):
    def test_blackbody_object(self):
        b = bx.blackbody(1500.0, 1.7, (1.0, -0.5, 0.25), "temperature")
        self.assertEqual(b, {"temperature": 1500.0, "intensity": 1.0, "tint": [1.0, 0.0, 0.25],
                             "attribute": "temperature"})
        self.assertEqual(bx.blackbody(-20.0, 0.5, (1, 1, 1))["temperature"], 0.0)

    def test_medium_json(self):
        m = bx.principled_volume([0.5, 0.5, 0.5], 1.0, [0.0, 0.0, 0.0], 0.0)
        m["blackbody"] = bx.blackbody(2000.0, 0.5, (1.0, 0.5, 0.5), "temperature")
        j = bx.medium_json("fire", m)
        self.assertEqual(j["blackbody"], {"temperature": 2000.0, "intensity": 0.5, "tint": [1.0, 0.5, 0.5]})
        m["blackbody"]["grid_ref"] = {"uri": "fire.vdb", "grid": "temperature", "scale": 2000.0}
        j = bx.medium_json("fire", m)
        self.assertEqual(j["blackbody"], {"uri": "fire.vdb", "grid": "temperature", "scale": 2000.0,
                                          "intensity": 0.5, "tint": [1.0, 0.5, 0.5]})
        m["blackbody"]["intensity"] = 0.0
        self.assertNotIn("blackbody", bx.medium_json("fire", m))

    def test_mix_scales_the_tint_and_add_keeps_one(self):
        a = bx.principled_volume([0.5, 0.5, 0.5], 1.0, [0.0, 0.0, 0.0], 0.0)
        a["blackbody"] = bx.blackbody(2000.0, 1.0, (1.0, 1.0, 1.0))
        b = bx.volume_scatter([1, 1, 1], 1.0, 0.0)
        m, _ = bx.mix_media(a, b, 0.25)
        self.assertEqual(m["blackbody"]["tint"], [0.75, 0.75, 0.75])
        self.assertEqual(a["blackbody"]["tint"], [1.0, 1.0, 1.0])  # not changed in place
        m, _ = bx.add_media(b, a)
        self.assertEqual(m["blackbody"]["temperature"], 2000.0)


class VolumeObjects(unittest.TestCase):
    def test_density_scale(self):
        # Blender's render space "OBJECT": 1/|M (1,1,1)/sqrt 3|; "WORLD": 1.
        self.assertAlmostEqual(bx.volume_density_scale([[0.5, 0, 0], [0, 0.5, 0], [0, 0, 0.5]], "OBJECT"), 2.0)
        self.assertAlmostEqual(bx.volume_density_scale([[0.5, 0, 0], [0, 0.5, 0], [0, 0, 0.5]], "WORLD"), 1.0)
        self.assertAlmostEqual(bx.volume_density_scale([[1, 0, 0], [0, 2, 0], [0, 0, 3]], "OBJECT"),
                               1.0 / math.sqrt(14.0 / 3.0))
        c, s = math.cos(0.7), math.sin(0.7)  # a rotation changes nothing
        self.assertAlmostEqual(bx.volume_density_scale([[c, -s, 0], [s, c, 0], [0, 0, 1]], "OBJECT"), 1.0)

    def test_half_voxel_offset(self):
        g = [[0.25, 0, 0, 1.0], [0, 0.25, 0, 2.0], [0, 0, 0.5, 3.0], [0, 0, 0, 1]]
        self.assertEqual(bx.half_voxel_offset(g), (0.125, 0.125, 0.25))


class Settings(unittest.TestCase):
    def test_max_depth(self):
        self.assertEqual(bx.brume_max_depth(0), 1)
        self.assertEqual(bx.brume_max_depth(12), 13)

    def test_render_settings(self):
        self.assertEqual(bx.render_settings(1920, 1080, 50, 64, 8),
                         {"width": 960, "height": 540, "spp": 64, "maxDepth": 9})

    def test_axes(self):
        self.assertEqual(bx.blender_to_gltf([1, 2, 3]), [1, 3, -2])


if __name__ == "__main__":
    if "--measurements" in sys.argv:
        i = sys.argv.index("--measurements")
        MEASUREMENTS = sys.argv[i + 1]
        Lights.m = Volumes.m = load()
        del sys.argv[i:i + 2]
    unittest.main()
