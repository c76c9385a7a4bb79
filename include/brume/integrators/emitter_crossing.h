// Crossing a transparent emitter (Material::transparent: a light surface as Cycles' lights
// are, which every ray passes through). A camera walk that crosses one gathers its emission
// as if the ray had ended there, weighted as an emitter hit (s = 0) among every strategy that
// makes the same path, and goes on unchanged. Shadow rays and connections pass through it
// (it is an invisible boundary to boundary_walk.h), so no other strategy sees it as a blocker.
//
// The bidirectional tracer's weight of that emitter hit needs the path as a vertex array that
// ends on the emitter: the camera walk's vertices up to the ray's start, then the crossing
// point as a surface vertex whose forward densities are those of the flight up to it (the
// free-flight pass densities of the pieces before it; the ray's direction density). Its
// reverse densities are the light's (bdpt_mis.h: connectionReverseDensities, s = 0).
#pragma once
#include <vector>

#include "brume/integrators/path_vertex.h"
#include "brume/scene/scene.h"

namespace brume {

// What a flight (free_flight_walk.h) knew where it crossed a transparent emitter.
struct FlightCrossing {
    float t = 0;        // along the flight's segment
    SurfaceHit hit;     // on the emitter
    Spectrum weight;    // the flight's throughput weight up to the crossing
    Channels fwd, rev;  // its free-flight densities up to the crossing, both ways
    bool crossedBefore = false;  // an invisible boundary lay before it on the segment
};

// A crossing as the camera walk's vertex `index` (the one its ray would have made there).
struct CrossingVertex {
    int index = 0;
    PathVertex vertex;
};

}  // namespace brume
