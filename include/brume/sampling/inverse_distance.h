// Points of the unit square drawn in proportion to 1/|x − c|: the film position within the
// pixel where a point light in fog projects, or next to it (light_pixels.h).
//
// Why. A camera ray passing a point light at distance D gathers in-scattered light ∝ 1/D
// (equi-angular sampling removes the 1/r² along the ray and leaves (θb − θa)/D). Over the
// pixel that holds the light's image, D ≈ k·|x − c| (x the film position, c the image), so
// with uniform film positions ∫ (1/D)² dA diverges: that pixel's variance is infinite, and
// with Sobol numbers its error falls slower than 1/n and dominates the image (fog room, single
// scattering, 256 spp: 10 pixels of 19200 held 58–85 % of the error). Drawn ∝ 1/|x − c|, a
// sample's weight 1/p ∝ |x − c| cancels the 1/D.
//
// Derivation. Split the square at c into four rectangles with c at a corner, and each along
// its diagonal into two right triangles with apex c, legs h (along one axis) and l (along the
// other). In polar coordinates about c (θ from the leg h, dA = r dr dθ),
//     ∫triangle dA / r = ∫0^Θ ∫0^(h/cosθ) dr dθ = h·∫0^Θ secθ dθ = h·asinh(l/h)   (tanΘ = l/h),
// so Z = Σ h·asinh(l/h) over the eight triangles. Within a triangle θ has CDF
// asinh(tanθ)/asinh(l/h) and, given θ, r is uniform on [0, h/cosθ]: with u, v uniform,
//     tanθ = sinh(u·asinh(l/h)),   x = c + v·h·(e_h + tanθ·e_l).
// The triangle is picked by u in proportion to its mass and u rescaled (monotone, so the
// sampler's strata map to strata). Density per unit area: 1/(Z·|x − c|).
// For c outside the square, in polar coordinates about c the square is {r_in(θ) ≤ r ≤ r_out(θ)}
// over an angle of less than π, and density ∝ 1/r per area is uniform in (r, θ): θ is drawn in
// proportion to r_out − r_in (the same secant integrals, edge by edge: far edges add, near
// ones subtract; inverted by bisection), then r uniformly on the chord.
#pragma once
#include "brume/sampling/sampler.h"

namespace brume {

// The sample: a point of [0, 1]² and 1/(its density per unit area), Z·|x − c| (0 at c).
struct InverseDistanceSample {
    float x = 0, y = 0;
    float weight = 0;
};

// Z = ∫[0,1]² dA / |x − c|.
float inverseDistanceNorm(float cx, float cy);
InverseDistanceSample sampleInverseDistance(float cx, float cy, Sample2 u);
// 1/(Z·|x − c|) (0 at c itself, where it is unbounded: a point of measure zero).
float inverseDistancePdf(float cx, float cy, float x, float y);

}  // namespace brume
