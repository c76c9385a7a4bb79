// Distance sampling on a medium segment in proportion to the solid angle Ω(x(t)) that an
// emissive triangle subtends at x(t) = o + t·d: the seed talk's open "analytical solution
// for area lights", as brume reads it. With an isotropic phase, an unoccluded uniform emitter
// of radiance L puts L·σs·Ω(x)/(4π) into the fog at x: Ω is the shape of what is collected.
//
// Ω is closed-form (spherical_triangle.h) but its integral along a line is not, so the
// density is tabulated, in the equi-angular angle towards the triangle's centroid c: with Δ
// and D as in equiangular.h, t = Δ + D·tanθ, dt = r²/D·dθ, r² = D² + (t − Δ)². Far from the
// emitter Ω ≈ A·cos/r², so q(θ) ∝ Ω(x(t(θ)))·r²/D is bounded and smooth over (−π/2, π/2),
// also for an unbounded segment; close to the emitter Ω → 2π and r²/D stays finite. q is
// piecewise linear over kBins equal angle bins (values at the bin edges; an unbounded
// segment's last just short of π/2), plus a tenth of its mean (a defensive share of plain
// equi-angular sampling), so
//   pdf(t) = q(θ(t)) · D / r²
// is exact and costs one atan2 and a table lookup; building the table costs kBins solid
// angles (in float: the table need only be a fixed function of the segment). For half of a
// rectangle (Light::partner) Ω and c are the whole rectangle's. D is kept ≥ a quarter of √A: any D > 0 is a valid change of variables, and a line
// through the centroid keeps a smooth map. The segment is clipped to where the light reaches
// (clipToLight: a one-sided emitter's front half-space).
#pragma once
#include "brume/integrators/equiangular_segment.h"

namespace brume {

struct SolidAngleDistance {
    static constexpr int kBins = 8;
    // Left uninitialised until solidAngleDistanceOn fills them (the path tracer keeps a few
    // per path, whether the scene has emissive triangles or not).
    double delta, D, thetaA, thetaB;
    float a, b;             // the clipped segment
    double node[kBins + 1];  // the density in θ at the bins' edges (linear in between)
    double cdf[kBins + 1];   // cumulative bin probabilities; cdf[kBins] = 1
};

// Whether seg passes close enough to `light` (an emissive triangle, or its rectangle) for
// distances by its solid angle to pay: within kSolidAngleReach·√A of its centroid. Further
// away the emitter looks like a point and equi-angular sampling towards a light point (the
// talk's ordering) does as well, without the table. A function of the geometry alone, so the
// strategy's density is exactly zero where it is not used.
constexpr float kSolidAngleReach = 3.0f;
bool solidAngleDistanceApplies(const Scene& scene, const Light& light, const MediumSegment& seg);

// Set up for `light` (an emissive triangle) on seg; false if the light is not a triangle or
// the clipped segment is empty.
bool solidAngleDistanceOn(const Scene& scene, const Light& light, const MediumSegment& seg, SolidAngleDistance* out);

// A distance for ξ ∈ [0, 1), within [a, b].
float sampleSolidAngleDistance(const SolidAngleDistance& s, float u);

// Its density at t (0 outside [a, b]).
float solidAngleDistancePdf(const SolidAngleDistance& s, float t);

}  // namespace brume
