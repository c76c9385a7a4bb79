// Light sources. Units are radiometric: point, spot and sphere lights carry a radiant
// intensity I [W/sr]; a directional light an irradiance E [W/m²]; an emissive triangle gets
// its radiance from its mesh's material.
#pragma once
#include <algorithm>
#include "brume/math/vec3.h"

namespace brume {

enum class LightKind { Point, Spot, Sphere, Directional, Triangle };

// An emissive triangle's shape: its corners in the mesh's order, unit front (counter-clockwise)
// normal ((0, 0, 1) when degenerate) and area.
struct EmitterTriangle {
    Vec3 p0, p1, p2;
    Vec3 n{0, 0, 1};
    float area = 0;
    // The unnormalised normal (p1 − p0) × (p2 − p0), as half-space tests take it.
    Vec3 edgeCross() const { return cross(p1 - p0, p2 - p0); }
};

struct Light {
    LightKind kind = LightKind::Point;
    Vec3 position;                 // point, spot, sphere: centre
    Vec3 direction{0, 0, -1};      // spot axis / directional travel direction (node −Z)
    Spectrum intensity{0.0f};      // I [W/sr] (point, spot, sphere) or E [W/m²] (directional)
    float radius = 0;              // sphere: uniform surface radiance I/(π r²)
    float cosInner = 1, cosOuter = 0;  // spot cone (glTF innerConeAngle, outerConeAngle)
    // Spot profile (spotAttenuation): glTF's (false), or Blender Cycles' (true; extras
    // "spotProfile": "cycles"), whose blend band is cosθ ∈ [cosOuter, cosOuter + spotSmooth].
    bool cyclesSpot = false;
    float spotSmooth = 0;
    int mesh = -1, triangle = -1;  // triangle: which mesh and which triangle of it
    // Triangle: the other half of a rectangle (two triangles of one emissive mesh that share a
    // diagonal and make a rectangle), or -1. Seen from a point, the rectangle is sampled as one
    // by solid angle (light_sampling.h), whichever half was picked.
    int partner = -1;
    Vec3 rectCorner, rectEdgeU, rectEdgeV;  // with a partner: the rectangle, perpendicular edges
    // Triangle: the emitter's area-weighted centroid and area (of the rectangle with a partner).
    Vec3 emitterCentre;
    float emitterArea = 0;
    // The emitter record, built once at load (Scene): a triangle's shape and whether its
    // material emits from both sides; every light's power (grey average, lightPower).
    EmitterTriangle shape;
    bool doubleSided = false;
    float power = 0;

    // What integrators ask of a light instead of its kind (docs/architecture.md, "A light"):
    // a delta light (point, spot, directional) has no area: only a connection reaches it, and
    // its sample draws no numbers.
    bool isDelta() const { return kind == LightKind::Point || kind == LightKind::Spot || kind == LightKind::Directional; }
    // A directional light: no position, its rays come from outside the scene.
    bool atInfinity() const { return kind == LightKind::Directional; }
    // An emitter with a surface that rays can hit (triangle, sphere).
    bool hasSurface() const { return kind == LightKind::Triangle || kind == LightKind::Sphere; }
    // A planar emitter with corners (an emissive triangle, half a rectangle with a partner):
    // sampled by area or by solid angle, and by distance tables along a ray
    // (solid_angle_segment.h); equi-angular sampling aims at a point drawn on it by area, not
    // at a position.
    bool isPlanar() const { return kind == LightKind::Triangle; }
};

// glTF spot attenuation: scale = 1/max(0.001, cosInner − cosOuter), offset = −cosOuter·scale,
// a = clamp(cosθ·scale + offset, 0, 1)², θ measured from the spot axis.
// Cycles' (3.4, `spot_attenuation`): cosθ inside the cone, 0 outside, times a smoothstep
// s²(3 − 2s), s = (cosθ − cosOuter)/spotSmooth, over the blend band (spotSmooth =
// (1 − cosOuter)·spot_blend).
inline float spotAttenuation(const Light& l, float cosTheta) {
    if (l.cyclesSpot) {
        if (!(cosTheta > l.cosOuter)) return 0.0f;
        const float t = cosTheta - l.cosOuter;
        if (!(l.spotSmooth > 0) || t >= l.spotSmooth) return cosTheta;
        const float s = t / l.spotSmooth;
        return cosTheta * s * s * (3.0f - 2.0f * s);
    }
    float scale = 1.0f / std::max(0.001f, l.cosInner - l.cosOuter);
    float a = std::min(1.0f, std::max(0.0f, cosTheta * scale - l.cosOuter * scale));
    return a * a;
}

}  // namespace brume
