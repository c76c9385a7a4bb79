// The numbers a light connection draws, only where the light needs them: every draw is a
// hash (sampling/sampler.h), and at a place of its own, so a draw skipped changes no other.
#pragma once
#include "brume/integrators/sample_dimensions.h"
#include "brume/sampling/sampler.h"
#include "brume/scene/scene.h"

namespace brume {

// The light a connection goes to, from the light distribution; a number only when there is a
// choice. The distribution must not be empty.
inline int pickLight(const Scene& scene, const Sampler& sampler, uint32_t dims, uint32_t repeat, float* pick) {
    const auto& d = scene.lightDistribution();
    return d.sample(d.size() > 1 ? sampler.get1D(dims + dim::kPick, repeat) : 0.5f, pick);
}

// The same, chosen by where the connection starts (light_selection.h): from the point x (a
// vertex's connection), or along the segment o + t·d, t ∈ [0, tEnd] (a connection that places
// its point on the segment). Power's pick where the scene's selection is not spatial.
inline int pickLightAt(const Scene& scene, const Sampler& sampler, uint32_t dims, uint32_t repeat, Vec3 x, float* pick) {
    const float u = scene.lights().size() > 1 ? sampler.get1D(dims + dim::kPick, repeat) : 0.5f;
    return scene.lightSelection().sampleAt(x, u, pick);
}
inline int pickLightAlong(const Scene& scene, const Sampler& sampler, uint32_t dims, uint32_t repeat, Vec3 o, Vec3 d,
                          float tEnd, float* pick) {
    const float u = scene.lights().size() > 1 ? sampler.get1D(dims + dim::kPick, repeat) : 0.5f;
    return scene.lightSelection().sampleAlong(o, d, tEnd, u, pick);
}

// The bidirectional tracer's light connection (s = 1) from camera vertex v, reached from the
// vertex before it at prev: at a surface it picks from v itself; in a medium along the ray
// from prev through v, unbounded (the ray's part in the medium would take a ray cast to find,
// and the MIS weights of every strategy must find this pick again from the path's positions
// alone: bdpt_mis.cpp, variantFactor). Its equi-angular variant, which places v on that ray
// after the pick, picks along the ray the same way. Where it starts: `along` is that ray's
// direction (the equi-angular variant's, before v is placed on it), or zero to take it from
// prev to v.
struct LightConnectionStart {
    Vec3 prev, v, along;
    bool medium;
    // The unit direction to pick along, or zero to pick from v.
    Vec3 direction() const {
        if (!medium) return Vec3(0.0f);
        if (dot(along, along) > 0) return along;
        const Vec3 d = v - prev;
        const float len = length(d);
        return len > 0 ? d / len : Vec3(0.0f);
    }
};
inline int sampleLightConnection(const Scene& scene, const LightConnectionStart& at, float u, float* pmf) {
    const Vec3 d = at.direction();
    return dot(d, d) > 0 ? scene.lightSelection().sampleAlong(at.prev, d, kInfinity, u, pmf)
                         : scene.lightSelection().sampleAt(at.v, u, pmf);
}
inline float lightConnectionPmf(const Scene& scene, Vec3 prev, Vec3 v, bool medium, int light) {
    const Vec3 d = LightConnectionStart{prev, v, Vec3(0.0f), medium}.direction();
    return dot(d, d) > 0 ? scene.lightSelection().pmfAlong(prev, d, kInfinity, light) : scene.lightSelection().pmfAt(v, light);
}
// That pick over power's, the factor by which the light connection's path density differs
// from the light subpath's start (every other strategy picks by power); 1 where picks are
// power's.
inline double lightConnectionPickRatio(const Scene& scene, Vec3 prev, Vec3 v, bool medium, int light) {
    if (!scene.lightSelection().spatial()) return 1.0;
    const float power = scene.lightDistribution().pmf(light);
    return power > 0 ? double(lightConnectionPmf(scene, prev, v, medium, light)) / double(power) : 1.0;
}

// The numbers for a point on the light (dimension `dim`): a triangle or sphere light has
// extent; a point, spot or directional light's sample is fixed and draws nothing.
inline Sample2 lightPointNumbers(const Light& light, const Sampler& sampler, uint32_t dim, uint32_t repeat) {
    return light.hasSurface() ? sampler.get2D(dim, repeat) : Sample2{0.5f, 0.5f};
}

}  // namespace brume
