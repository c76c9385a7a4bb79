// Free flight from a vertex along a ray through the scene's media and invisible boundaries:
// one Medium::sampleDistance per piece of the ray (boundary_walk.h) until a collision, a
// surface or an escape. The bidirectional walks use it for every edge; the densities of both
// walk directions are the products over the pieces.
#pragma once
#include "brume/integrators/boundary_walk.h"
#include "brume/integrators/emitter_crossing.h"
#include "brume/integrators/mis.h"
#include "brume/integrators/sample_dimensions.h"

namespace brume {

struct Flight {
    enum class End { Collision, Surface, Escape };
    End end = End::Escape;
    float t = 0;                     // along the segment: the collision or the surface hit
    SurfaceHit hit;                  // End::Surface
    const Medium* medium = nullptr;  // End::Collision: where it happened
    MediumStack media;               // the media where the flight ended
    Spectrum weight{1.0f};           // product of the pieces' throughput weights
    Channels fwd, rev;               // free-flight densities per channel: this flight's, a walk back's
    bool crossed = false;            // passed an invisible boundary
    float firstEnd = kInfinity;      // where the segment's first piece ends
};

// What a camera walk's flight gathers from emissive media (Medium::emitted): on each piece it
// reaches, the flight's weight up to the piece times the piece's emission. Only the camera
// walk makes these paths, so their weight runs over the colour channels alone (bdpt_mis.h,
// "over channels"): n / Σ_c r_c^β, with r_c the density, in channel c over the hero's, of
// the path to the piece: the walk's prefix (PathVertex::channelRatio) times the pass densities
// of the pieces before it (1 where the flight passes through).
struct FlightEmission {
    Channels prefix{1.0};
    int hero = 0;
    int channels = 1;  // Scene::mediumChannels
    MisHeuristic heuristic = MisHeuristic::Power;
    uint32_t dims = 0;        // dim::mediumEmission of the vertex the flight leaves
    // The vertex the flight leaves sampled the volume lights (grey scenes only: then
    // channels = 1): each point of a medium they sample is weighted against them, the ray's
    // direction density at that vertex being dirPdf (volume_light_sampling.h).
    bool againstVolumeLights = false;
    float dirPdf = 0;
    Spectrum gathered{0.0f};  // (out) per unit of throughput at the flight's start
};

// Along seg (a ray: leaving(), end +∞). startIsPoint: it starts at a medium vertex (the
// reverse walk would scatter there). channels: the probabilities with which each colour
// channel drives the distance in homogeneous media (Medium::sampleDistance: the hero
// channel); tracking: the channel weights of the real/null choice in grid media, whose
// tentative distances are the same for every channel and whose densities (stand-ins) are grey,
// so that the choice enters no MIS weight and may follow the throughput. Numbers: dims + kDistance and
// dims + kChannel, with the piece index as repeat. passThrough: no collision is sampled; every
// medium piece is passed with weight T and forward density 1 (no numbers drawn). emission:
// gathers emissive media's emission (camera walks; null: none). crossings: where the flight
// crossed transparent emitters before it ended (emitter_crossing.h; null: not wanted).
Flight sampleFlight(const Scene& scene, const WalkSegment& seg, const MediumStack& media, bool startIsPoint,
                    Spectrum channels, Spectrum tracking, const Sampler& sampler, uint32_t dims, PathStats& stats,
                    bool passThrough = false, FlightEmission* emission = nullptr,
                    std::vector<FlightCrossing>* crossings = nullptr);

}  // namespace brume
