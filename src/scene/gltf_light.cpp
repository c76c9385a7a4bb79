// glTF loader: KHR_lights_punctual lights (plus brume's sphere lights, extras.radius, and
// Cycles' spot profile, extras.spotProfile and spotBlend), in
// radiometric units: color × intensity is W/sr for point, spot and sphere lights and W/m² for
// directional ones, with no photometric 683 lm/W factor.
#include <algorithm>
#include <cmath>

#include "brume/scene/gltf_detail.h"

namespace brume::gltf {

namespace {

constexpr double kHalfPi = 1.57079632679489661923;

double nonNegative(const Source& src, double v, const std::string& field, const char* what) {
    if (!std::isfinite(v)) src.fail(field, std::string("non-finite ") + what + " " + num(v));
    if (v < 0) src.fail(field, std::string("negative ") + what + " " + num(v));
    return v;
}

}  // namespace

Light makeLight(const Source& src, const tinygltf::Model& model, int lightIndex, const Mat4& world,
                const std::string& field) {
    checkIndex(src, lightIndex, model.lights.size(), field, "light");
    const tinygltf::Light& gl = model.lights[size_t(lightIndex)];
    const std::string lf = at("extensions.KHR_lights_punctual.lights", size_t(lightIndex));
    Light l;

    Spectrum color(1.0f);
    if (!gl.color.empty()) {
        if (gl.color.size() != 3) src.fail(lf + ".color", "expected 3 numbers, got " + std::to_string(gl.color.size()));
        for (int c = 0; c < 3; ++c)
            color[c] = float(nonNegative(src, gl.color[size_t(c)], lf + ".color", "color component"));
    }
    const double intensity = nonNegative(src, gl.intensity, lf + ".intensity", "intensity");
    l.intensity = color * float(intensity);
    if (!isFinite(l.intensity)) src.fail(lf + ".intensity", "intensity " + num(intensity) + " is too large");

    l.position = world.point(Vec3(0, 0, 0));
    const Vec3 axis = world.vector(Vec3(0, 0, -1));
    const float axisLength = length(axis);
    const bool hasAxis = axisLength > 0 && std::isfinite(axisLength);
    if (hasAxis) l.direction = axis / axisLength;

    if (gl.type == "point") {
        l.kind = LightKind::Point;
        if (const tinygltf::Value* r = member(gl.extras, "radius")) {
            const std::string field = lf + ".extras.radius";
            double radius = nonNegative(src, finiteNumber(src, *r, field), field, "radius");
            if (radius > 0) {
                l.kind = LightKind::Sphere;
                l.radius = float(radius);
            }
        }
    } else if (gl.type == "spot" || gl.type == "directional") {
        if (!hasAxis) src.fail(field, "the node transform is degenerate, so the light has no direction");
        l.kind = gl.type == "spot" ? LightKind::Spot : LightKind::Directional;
        if (l.kind == LightKind::Spot) {
            const double inner = gl.spot.innerConeAngle, outer = gl.spot.outerConeAngle;
            if (!(std::isfinite(inner) && std::isfinite(outer) && 0 <= inner && inner < outer &&
                  outer <= kHalfPi + 1e-9))
                src.fail(lf + ".spot", "need 0 <= innerConeAngle < outerConeAngle <= pi/2, got innerConeAngle " +
                                           num(inner) + ", outerConeAngle " + num(outer));
            l.cosInner = float(std::cos(inner));
            l.cosOuter = float(std::max(0.0, std::cos(outer)));
            // extras "spotProfile": "gltf" (the default) or "cycles", and "spotBlend" (Blender's
            // spot_blend, 0 to 1) for the latter: Cycles' profile cut at outerConeAngle.
            if (const tinygltf::Value* p = member(gl.extras, "spotProfile")) {
                const std::string pf = lf + ".extras.spotProfile";
                if (!p->IsString() || (p->Get<std::string>() != "gltf" && p->Get<std::string>() != "cycles"))
                    src.fail(pf, "expected \"gltf\" or \"cycles\"");
                l.cyclesSpot = p->Get<std::string>() == "cycles";
            }
            if (const tinygltf::Value* b = member(gl.extras, "spotBlend")) {
                const std::string bf = lf + ".extras.spotBlend";
                if (!l.cyclesSpot) src.fail(bf, "spotBlend needs \"spotProfile\": \"cycles\"");
                const double blend = finiteNumber(src, *b, bf);
                if (blend < 0 || blend > 1) src.fail(bf, "spotBlend " + num(blend) + " must be in [0, 1]");
                l.spotSmooth = float((1.0 - double(l.cosOuter)) * blend);
            }
        }
    } else {
        src.fail(lf + ".type", "unknown light type '" + gl.type + "'");
    }
    return l;
}

}  // namespace brume::gltf
