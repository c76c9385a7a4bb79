// Where each sampling decision of a pixel sample reads its numbers (sampling/sampler.h): a
// dimension derived from the decision's place in the path, never from how many numbers came
// before. One table for both integrators:
//
//   film jitter                                  kFilmJitter (2D)
//   hero channel of a BDPT sample (coloured media) kHeroChannel
//   light subpath start: light pick, emission    kLightStart + kPick, kPosition (2D), kEmitDir (2D)
//   camera vertex k, light vertex k (the walk    walkVertex(side, k) + kDistance, kChannel,
//     that leaves vertex k and makes k + 1)        kDirection (2D), kLobe, kRoulette, kGuide
//                                                  (guided or unguided direction, path_guide.h),
//                                                  kKeep (whether a dark training record is kept)
//   connection (s, t) of the BDPT                connection(s, t) + kPick, kLightPoint (2D), kEquiAngular,
//                                                  kConnect (whether a general connection is made)
//   pt at camera vertex k: next-event estimate   connection(1, k + 1) (same fields; kConnect:
//                                                  whether it is made, connection_shares.h)
//   pt on the segment leaving camera vertex k:   equiAngularSegment(k) + kPick, kAnchor (2D),
//     equi-angular strategy                        kEquiAngular, kLightPoint (2D), kConnect
//   pt on the segment leaving camera vertex k:   solidAngleSegment(k) + kPick, kEquiAngular
//     solid-angle distance strategy                (the distance), kLightPoint (2D)
//   the ray leaving camera vertex k, both        mediumEmission(k) + kEmission (per piece:
//     tracers: emissive media's estimate           the seed of Medium::emitted)
//   pt at camera vertex k: next-event estimate   volumeLight(k) + kPick, kLightPoint (2D),
//     towards emissive media                       kAnchor (the point in its brick)
//
// A decision repeated a variable number of times on one place (free flight through several
// invisible-boundary pieces, pt's equi-angular strategy per piece) reads its dimension with
// repeat 0 for the first time and repeat i for the i-th further one (Sampler::get1D). The
// dimensions are far apart, not dense: the independent sampler hashes them, and Sobol gives
// each dimension (or pair) its own scrambled sequence, seeded by the dimension (sampler.h).
#pragma once
#include <cstdint>

namespace brume::dim {

constexpr uint32_t kFilmJitter = 0;
constexpr uint32_t kHeroChannel = 2;
constexpr uint32_t kLightStart = 8;
constexpr uint32_t kPosition = 1, kEmitDir = 3;  // after kPick (0)
constexpr uint32_t kMade = 5;  // whether the light subpath is traced at all (bdpt_light_made)

// Fields of a walk block (8 dimensions a vertex).
constexpr uint32_t kDistance = 0, kChannel = 1, kDirection = 2, kLobe = 4, kRoulette = 5, kGuide = 6, kKeep = 7;
// Fields of a connection block (8 dimensions a connection).
constexpr uint32_t kPick = 0, kLightPoint = 1, kAnchor = 3, kEquiAngular = 5, kConnect = 6;

constexpr uint32_t kBlock = 8;
constexpr uint32_t kMaxPlace = 1024;  // vertices per subpath, as BDPT stores them

enum class Side : uint32_t { Camera = 0, Light = 1 };

// k = 0 is the camera or light vertex the walk starts from.
constexpr uint32_t walkVertex(Side side, int k) {
    return 0x100u + (uint32_t(side) * kMaxPlace + uint32_t(k)) * kBlock;
}
constexpr uint32_t connection(int s, int t) {
    return 0x10000u + (uint32_t(s) * (kMaxPlace + 1) + uint32_t(t)) * kBlock;
}
constexpr uint32_t equiAngularSegment(int k) { return 0x1000000u + uint32_t(k) * kBlock; }
constexpr uint32_t solidAngleSegment(int k) { return 0x1800000u + uint32_t(k) * kBlock; }
constexpr uint32_t kEmission = 0;
constexpr uint32_t mediumEmission(int k) { return 0x2000000u + uint32_t(k) * kBlock; }
constexpr uint32_t volumeLight(int k) { return 0x2800000u + uint32_t(k) * kBlock; }

}  // namespace brume::dim
