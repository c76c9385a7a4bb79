// What samples cost, in units of one ray of the bidirectional tracer's camera walk, counted
// from the parts they made (PathCounts, path_stats.h): the efficiency-aware tracer's stand-in for
// time (allocation_planner.h), which would make the image depend on the machine's load.
//
// Bidirectional tracer: each part's rays, weighted by what one costs with everything that
// comes with it (the vertex, its densities and MIS sums, the weight of a connection, the
// placement of an equi-angular vertex), plus a fixed cost per sample. Fitted to the time per
// pass of all 18 allocations on six bench scenes at 160x120 (1 thread, median of 3; the
// free-flight light connection tied to the camera-walk ray): within 12 % for the median
// allocation and 36 % for the worst, where plain ray counts were off by 19 % and 76 %.
//
// Path tracer (pt --connect mis and density, the candidates auto renders): a fixed cost per
// sample, its walk's rays, and its light connections by part: calls at vertices, calls on
// segments (equi-angular or product: placing the vertex), rays by an emitter's solid angle
// (the tables of solid_angle_segment.h come with them). Fitted (non-negative least squares
// on relative error) to its time per sample over that of `bdpt --connect mis` on the same
// scene, counted with the weights above, on the 14 bundled scenes, single scattering and
// full transport (1 thread, 160x120, best of 2): median error 11 % (density) and 14 % (mis),
// worst 0.56× (a panel light, single scattering) and 1.75× (dusk_haze: most of it was the
// bidirectional tracer's coloured MIS in long double exp and log, since removed; the pilot's
// rating of the path tracer there is now 1.3× what it measures, docs/results.md); on the
// validation scenes, which it was not fitted on, see docs/results.md.
#pragma once
#include <cstdint>

#include "brume/integrators/path_stats.h"

namespace brume {

namespace bdpt_cost {
constexpr double kSample = 10.6, kCameraWalk = 1.0, kLightWalk = 2.71, kLightConnection = 1.0, kLightConnectionEa = 4.50,
                 kCameraConnection = 3.07, kCameraConnectionEa = 5.71, kGeneralConnection = 2.54;
}  // namespace bdpt_cost

namespace pt_cost {
constexpr double kSample = 3.2, kWalk = 1.7, kVertexCall = 0.2, kSegmentCall = 2.6, kSolidAngleRay = 9.0;
// What leaving one light connection out saves (connection_shares.h), in the same units: the
// fit above gives the walk most of the time of A's shadow ray, which is always made beside it,
// so A's call alone (0.2) undercounts what qA = 0 saves 6×. Measured by leaving each out
// (64 spp, 160x120, 2 threads, two runs alternated): A on bench_thin_near and bench_forward
// (full transport) 1.23 and 1.19 per ray, plus its call; C on bench_thin_near 1.83 per call
// that traces; D on bench_panel (single scattering) 8.7 per ray. (On val_thin_lamp, not
// measured for this, A's ray cost 1.33.)
constexpr double kVertexRaySaved = 1.2, kSegmentCallSaved = 1.8, kSolidAngleRaySaved = 8.7;
}  // namespace pt_cost

// The cost of `samples` samples of the bidirectional tracer that counted `n`, every part as it
// was made.
double bidirectionalCost(const BidirectionalCounts& n, double samples);
// The cost of the path-tracer samples that counted `n` (their number among them).
double pathTracerCost(const PathTracerCounts& n);

}  // namespace brume
