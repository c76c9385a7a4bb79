// MIS weights of the bidirectional strategies, including the equi-angular variants of
// connection vertices (docs/mis.md derives every line). Each weight costs O(1): the ratio
// recursion over the parts of both subpaths that no connection changes is summed once per
// subpath (misPrefixes), and only the terms next to the connection are evaluated per
// connection (misWeight).
#pragma once
#include "brume/integrators/mis.h"
#include "brume/integrators/path_tracer.h"
#include "brume/integrators/path_vertex.h"

namespace brume {

struct MisSettings {
    MisHeuristic heuristic = MisHeuristic::Power;
    ConnectMode connect = ConnectMode::Density;
    // Equi-angular densities of connection vertices: false = the stand-in over the unbounded
    // ray from the previous vertex (docs/mis.md); true = over the part of that ray in its
    // medium, clipped as the sampler clips it (one ray cast per density; for measurements).
    bool exactEquiAngular = false;
    int width = 0, height = 0;  // the film, for clipping to the view frustum
};

// What equi-angular sampling towards vertex `a` aims at: a light vertex, or the camera walk's
// hit on an emitter that ends the path (endsPath), aims at its light's anchor and is clipped
// to what the light can reach; the pinhole at itself, clipped to the frustum; any other
// vertex at itself. valid = false for a directional light, which has no position.
struct EquiAngularAim {
    bool valid = false;
    Vec3 anchor;
    const Light* clip = nullptr;  // light whose cone / front half-space clips the segment
    bool toCamera = false;        // clip to the view frustum
};
EquiAngularAim equiAngularAim(const Scene& scene, const PathVertex& a, bool endsPath);

// The equi-angular density (per unit length) with which medium vertex v is placed on the ray
// from prev aimed at `aim`, as the weights use it (stand-in or exact, by settings).
double equiAngularDensity(const Scene& scene, const PathVertex& prev, const PathVertex& v, const EquiAngularAim& aim,
                          MisSettings settings);

// What misWeight needs of one subpath, from the densities its walk stored (n vertices):
// prefix[j] = Σ_{i ≤ j} Π_{m=i..j} r_m^β · V_i (camera: i ≥ 1; light: i ≥ 0) and the variant
// factors V. misWeight reads prefix[t−3] (camera) and prefix[s−3] (light), which no
// connection alters, and the V that do not involve the connection.
struct SubpathMis {
    const double* prefix;
    const double* variant;
};
void misPrefixes(const Scene& scene, const PathVertex* path, int n, bool cameraSide, MisSettings settings,
                 double* prefix, double* variant);

// The weight of the strategy (s, t) for the joined subpaths, whose four vertices next to the
// connection already carry this connection's reverse densities. ownEquiAngular: the sample is
// the equi-angular variant. connectionCrossed: the connecting segment crossed an invisible
// boundary. For s = 1 (a fresh light sample joined) lightMis is not read.
double misWeight(const Scene& scene, const PathVertex* light, const PathVertex* camera, int s, int t,
                 MisSettings settings, bool ownEquiAngular, bool connectionCrossed, const SubpathMis& lightMis,
                 const SubpathMis& cameraMis);

}  // namespace brume
