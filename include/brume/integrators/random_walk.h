// Extends a camera or light subpath by free-flight and BSDF/phase sampling, recording each
// vertex with its forward and reverse area densities (path_vertex.h).
#pragma once
#include "brume/guiding/guiding_field.h"
#include "brume/integrators/integrator.h"
#include "brume/integrators/boundary_walk.h"
#include "brume/integrators/emitter_crossing.h"
#include "brume/integrators/mis.h"
#include "brume/integrators/path_vertex.h"
#include "brume/integrators/sample_dimensions.h"

namespace brume {

struct WalkStart {
    WalkSegment ray;     // leaving path[0] (boundary_walk.h: leaving())
    MediumStack media;   // media the ray starts in
    Spectrum beta;       // throughput after path[0] and the direction choice
    float pdfDir = 0;    // solid-angle density of ray.d at path[0]
    int width = 0, height = 0;  // the image, for the camera's direction density
    dim::Side side = dim::Side::Camera;  // whose dimensions the walk reads (sample_dimensions.h)
    int hero = 0;        // the colour channel that drives free flight (bdpt_mis.h)
    // From this vertex index on, rays pass through media without sampling a collision (weight
    // T, free-flight density 1): the camera walk's vertex past the last scattering event a
    // --max-depth allows, which only an emitter hit can use (bdpt.cpp).
    int passFrom = 1 << 30;
    // At this vertex index, after a vertex that is not specular, the ray passes through
    // media too: the camera walk's last scattering event where equi-angular light
    // connections cover the medium (bdpt.cpp; bdpt_mis.h, MisSettings::passFirstAt).
    int passFirstAt = 1 << 30;
    // The camera walk's guide (`--guiding on`, docs/path-guiding.md): the frozen guiding field.
    // A camera walk samples its directions from the guided mixture (guided_phase.h) and, with
    // pixelValue (the pixel as the training passes saw it) > 0, survives by it (guided
    // survival; else the throughput roulette). A light walk is not guided: the field only
    // gives the densities with which the camera walk would retrace its edges (pdfRev).
    const GuidingField* guide = nullptr;
    float pixelValue = -1;
    // The heuristic of the channel weights of what a camera walk's rays gather from emissive
    // media (PathVertex::edgeEmission).
    MisHeuristic heuristic = MisHeuristic::Power;
    // The camera walk's vertices 1 … volumeLightsUpTo that are not specular sample the volume
    // lights (bdpt.cpp, volumeLightConnection): the rays leaving them weigh what they gather
    // against that. 0: none.
    int volumeLightsUpTo = 0;
    // A camera walk appends here each transparent emitter its rays cross, as the vertex the
    // ray would have made there (emitter_crossing.h; null: none wanted).
    std::vector<CrossingVertex>* crossings = nullptr;
};

// path[0] is filled in by the caller (camera or light vertex). Appends vertices path[1..],
// at most maxVertices − 1 of them and at most maxScatter scattering ones (surfaces that are
// not invisible boundaries, and medium points); stops at an escape, a sphere light, a black
// throughput or Russian roulette (from the fourth vertex on, or guided survival). Returns the vertex count,
// path[0] included.
int randomWalk(const Scene& scene, const WalkStart& start, TransportMode mode, int maxScatter, const Sampler& sampler,
               PathVertex* path, int maxVertices, PathStats& stats);

// The densities of a camera path path[0 … count − 1] that ends on a crossing's vertex, as
// randomWalk computes them for its own vertices (the last vertex's reverse ones are left to
// the weights: bdpt_mis.h).
void crossingPathDensities(const Scene& scene, PathVertex* path, int count, int width, int height,
                           const GuidingField* guide);

}  // namespace brume
