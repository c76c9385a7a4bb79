// Which light a connection goes to, chosen by where it starts: from a point x (a surface
// vertex), in proportion to what each light would give x unoccluded; along a ray segment in a
// medium (every connection made on it or from a free-flight vertex on it), to what it would
// give the segment's points. Power alone (Scene::lightDistribution) picks the far lamps of a
// street as often as the near one, whose light a point in the fog mostly gets.
//
// Weights (grey intensities; unoccluded, no transmittance, no phase function):
// - a point x and a point, sphere or spot light at p of intensity I: I·spot(x)/|x − p|² (the
//   squared distance at least r² for a sphere);
// - a point x and an emissive triangle or rectangle of power Φ, area A, normal n, centre p:
//   (Φ/π)·cos⁺(n, x − p)/max(|x − p|², A) (|cos| for a two-sided one), its radiance times the
//   solid angle it subtends from far away;
// - a segment o + t·d, t ∈ [0, t1], and a point, sphere or spot light at p of intensity I (a
//   spot without its cone): ∫ I/|o + t·d − p|² dt = I·(θ1 − θ0)/D, D the distance from p to
//   the ray's line (at least the sphere's radius), θ the angles of the ends seen from p's foot
//   on the line (the integral equi-angular sampling inverts).
// From a point every light is steered: P(i) = 0.1·power(i) + 0.9·w_i/Σw. Along a segment only
// the point-like lights are, within their power's share P_s: P(i) = 0.1·power(i) +
// 0.9·P_s·w_i/Σw; planar emitters keep power's pick there (a large panel close by is far from a
// point, and its connections' variance, not its mean, is what it needs samples for: steering
// them too cost the panel room 1.2x its variance). The floor keeps every pick that power would
// make above a tenth of it, whatever a weight overlooks (an occluder, the spot's cone along a
// segment): any such choice is unbiased, the weights only steer it.
//
// Used where every pick is cheap to weigh again: 2 to kMaxLights lights, none directional
// (whose irradiance has no distance to compare); otherwise every function below returns
// power's pick, bit for bit as lightDistribution(). The sums over the lights of the last point
// and the last segment are kept per thread: a path weighs the same point or segment several
// times (its own pick, then each other technique's density of it).
#pragma once
#include <cstdint>
#include <vector>
#include "brume/math/vec3.h"
#include "brume/sampling/distribution1d.h"

namespace brume {

struct Light;

class LightSelection {
public:
    static constexpr int kMaxLights = 32;

    LightSelection() = default;
    LightSelection(const std::vector<Light>& lights, const Distribution1D& power);

    // Whether picks depend on where they start (else they are power's).
    bool spatial() const { return spatial_; }

    // From a point x: the light for u ∈ [0, 1), and *pmf its probability.
    int sampleAt(Vec3 x, float u, float* pmf) const;
    float pmfAt(Vec3 x, int light) const;

    // Along the segment o + t·d, t ∈ [0, tEnd] (d unit; tEnd may be +∞): power's pick, to the
    // bit, unless there are at least two point-like lights to steer between.
    int sampleAlong(Vec3 o, Vec3 d, float tEnd, float u, float* pmf) const;
    float pmfAlong(Vec3 o, Vec3 d, float tEnd, int light) const;

    // The unnormalised weights (above) of every light, for tests.
    std::vector<float> weightsAt(Vec3 x) const;
    std::vector<float> weightsAlong(Vec3 o, Vec3 d, float tEnd) const;

private:
    // What the weights read, light by light, as arrays the loops below run through. The two
    // halves of a rectangle (Light::partner) share its centre and area, so they get the same
    // pick (light_sampling.h's P(rectangle)/P(light) stays 2 wherever the pick starts).
    struct Sources {
        std::vector<float> px, py, pz;  // position or emitter centre
        std::vector<float> nx, ny, nz;  // planar: unit normal; spot: axis
        std::vector<float> intensity;   // grey I, or L·A (Φ/π of one side) for a planar emitter
        std::vector<float> minD2;       // smallest squared distance a weight uses
        std::vector<float> planar, twoSided;  // 1 or 0: a planar emitter, a two-sided one
        std::vector<float> spotScale, spotOffset;  // glTF's spot profile (scale 0, offset 1: none)
        std::vector<float> cycles, cosOuter, invSmooth;  // Cycles' spot profile (cycles 1)
        std::vector<float> power;       // power's pmf
    };
    void weightsAt(Vec3 x, float* w) const;
    void weightsAlong(Vec3 o, Vec3 d, float tEnd, float* w) const;
    struct Table;  // the picks' cumulative sums for one point or segment (light_selection.cpp)
    const Table& tableAt(Vec3 x) const;
    const Table& tableAlong(Vec3 o, Vec3 d, float tEnd) const;
    void fill(Table& t, const float* w, bool pointLikeOnly) const;
    int sample(const Table& t, float u, float* pmf) const;
    float pmf(const Table& t, int light) const;

    // The point-like lights alone, in the same arrays, for the segment's loop (its lanes are
    // then all lights it steers: the street's four among sixteen), and their indices.
    struct PointLike {
        std::vector<float> px, py, pz, intensity, minD2;
        std::vector<int> index;
    };
    Sources src_;
    PointLike along_;
    int count_ = 0;
    const Distribution1D* power_ = nullptr;
    bool spatial_ = false;
    bool steerAlong_ = false;  // spatial_ with at least two point-like lights
    uint64_t id_ = 0;  // tells this selection's kept sums from another's
};

}  // namespace brume
