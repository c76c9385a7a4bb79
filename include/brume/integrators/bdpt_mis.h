// MIS weights of the bidirectional strategies, including the equi-angular variants of
// connection vertices (docs/mis.md derives every line). Each weight costs O(1): the ratio
// recursion over the parts of both subpaths that no connection changes is summed once per
// subpath and kept in its vertices (misPrefixes), and only the terms next to the connection are evaluated per
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
    // Whether general connections (s, t ≥ 2) have equi-angular variants (BdptOptions), and the
    // probability with which each is made (BdptOptions::generalConnection).
    bool generalEquiAngular = false;
    double generalConnection = 1.0;
    int width = 0, height = 0;  // the film, for clipping to the view frustum
    // Colour channels the weights run over (Scene::mediumChannels: 1 without coloured media)
    // and the sample's hero channel, which drove every free-flight distance of both walks.
    int channels = 1;
    int hero = 0;
    // The camera walk passes through media from this vertex index on (WalkStart::passFrom:
    // --max-depth m gives m + 1): a camera walk makes a vertex there with free-flight density 1.
    int passFrom = 1 << 30;
    // And at this index (m, the last scattering event), after a vertex that is not specular,
    // where the equi-angular light connection covers the medium (WalkStart::passFirstAt): no
    // medium vertex there (density 0: its strategies lose their free-flight variants), and a
    // surface with free-flight density 1.
    int passFirstAt = 1 << 30;
    // The rest of the allocation in force (BdptOptions): how many camera connections (t = 1)
    // a sample makes (1, or 0 without light tracing), and whether light (s = 1) and camera
    // (t = 1) connections have equi-angular variants. A strategy made n times has its
    // density counted n times in every weight; one made 0 times drops out of them.
    double cameraConnection = 1.0;
    bool equiAngularLight = true, equiAngularCamera = true;
    // Whether an equi-angular variant that is on replaces the free-flight one at a medium
    // vertex (BdptAllocation::equiAngularOnly; --connect equiangular and product always do).
    bool equiAngularOnly = false;
    // On paths of one scattering event (camera, x1, light) only: a factor on the camera
    // connection's count in every weight, learned by direct_light_tracing.h (variance-aware
    // MIS; 1 = the plain heuristic). The camera connection is still made cameraConnection
    // times; only its share of these paths changes, so the weights still sum to one.
    double directLightTracing = 1.0;
    // For direct_light_tracing.h's statistics, a one-event path weighted as if one family of
    // its strategies were alone: the camera side (every strategy but the camera connection)
    // or light tracing (the camera connection's variants only).
    enum class Alone { None, CameraSide, LightTracing };
    Alone directAlone = Alone::None;
    // The camera walk's guide (`--guiding on`, random_walk.h): every density that is the
    // camera walk's direction choice is the guided mixture (path_vertex.h,
    // vertexDirectionPdf). Null: no guiding.
    const GuidingField* cameraGuide = nullptr;
};

// Whether a connection's equi-angular variant, where it is on at a medium vertex, replaces
// the free-flight variant (its count 0 there) rather than adding to it.
inline bool equiAngularReplacesFreeFlight(const MisSettings& st) { return variantOnly(st.connect) || st.equiAngularOnly; }

// Whether the camera walk passes through media to make its vertex j, after a vertex that is
// specular (prevDelta) or not.
inline bool cameraWalkPasses(const MisSettings& st, int j, bool prevDelta) {
    return j >= st.passFrom || (j == st.passFirstAt && !prevDelta);
}

// Stores in each vertex of a subpath (n vertices) the sums misWeight needs of it, from the
// densities its walk stored: misPrefix of vertex j = Σ_{i ≤ j} Π_{m=i..j} r_m^β · V_i
// (camera: i ≥ 1; light: i ≥ 0) and misVariant = V_j. misWeight reads the prefix at z(t−3) and
// y(s−3), which no connection alters, and the V that do not involve the connection.
void misPrefixes(const Scene& scene, PathVertex* path, int n, bool cameraSide, MisSettings settings);

// The MIS sums misPrefixes keeps in a vertex, copied out of it (misPerCountLanes).
struct MisSums {
    double misPrefixGrey = 0, misVariantGrey = 1;
    Channels misPrefix{0.0};
    Channels misVariant{0.0};
};
void copyMisSums(const PathVertex* path, int n, MisSums* out);

// What a strategy's weight needs of the connection it made between y(s−1) and z(t−1).
struct StrategyJoin {
    Channels freeFlightToCamera;    // a walk y(s−1) → z(t−1) stopping at z(t−1) (Connection::freeFlightToA)
    Channels freeFlightToLight;     // a walk z(t−1) → y(s−1) stopping at y(s−1) (Connection::freeFlightToB)
    bool crossed = false;           // the connecting segment crossed an invisible boundary
    bool equiAngular = false;       // the sample is the strategy's equi-angular variant
    // For an equi-angular variant, its vertex's equi-angular density p_ea (per unit length, as
    // the weights see it) from the placement, so the weight need not compute it again (0: it
    // does).
    double ownEquiAngularDensity = 0;
};

// The weight of the strategy (s, t) for the joined subpaths (for s = 1 `light` is the sampled
// light vertex alone, whose MIS sums are not read). The reverse densities of the four vertices
// next to the connection, which only this connection determines, are set for the weight and
// put back after (connectionReverseDensities).
double strategyWeight(const Scene& scene, PathVertex* light, int s, PathVertex* camera, int t, const StrategyJoin& join,
                      MisSettings settings, double* perCount = nullptr);

// Sets pdfRev of z(t−1), z(t−2), y(s−1), y(s−2) (those that exist) to the densities with which
// the other subpath's walk, continued through the connection, would have made them.
void connectionReverseDensities(const Scene& scene, PathVertex* light, int s, PathVertex* camera, int t,
                                const StrategyJoin& join, MisSettings settings);

// The four vertices whose pdfRev that sets, in this order (nullptr where one does not exist):
// z(t−1), z(t−2), y(s−1), y(s−2).
void connectionNeighbours(PathVertex* light, int s, PathVertex* camera, int t, PathVertex* out[4]);

// The weight for joined subpaths whose four vertices next to the connection already carry its
// reverse densities (strategyWeight calls this; the weight checker's derivation follows it).
// *perCount (if given) receives the weight divided by the own strategy's count (for the
// balance heuristic: the own density over Σ_k n_k·p_k), which exists even where that count is
// 0; +∞ where no strategy of the allocation can make the path.
double misWeight(const Scene& scene, const PathVertex* light, const PathVertex* camera, int s, int t,
                 MisSettings settings, bool ownEquiAngular, bool connectionCrossed, double ownEquiAngularDensity = 0,
                 double* perCount = nullptr);

// misWeight's perCount for one joined path under `lanes` (7 or 14) settings at once, the same
// bits as one misWeight per setting, for the planner's statistics (allocation_statistics.cpp):
// what the settings share (the geometry, ρ, the light's pick, the densities) is found once. The
// settings may differ in heuristic, generalConnection, cameraConnection and the
// equi-angular switches (equiAngularLight, equiAngularCamera, equiAngularOnly), in nothing
// else. The subpaths' sums under lane ℓ's settings (misPrefixes, then copyMisSums) are at
// cameraSums[ℓ · cameraStride + i] and lightSums[ℓ · lightStride + i].
constexpr int kMaxMisLanes = 14;
void misPerCountLanes(const Scene& scene, const PathVertex* light, const PathVertex* camera, int s, int t,
                      const MisSettings* settings, int lanes, bool ownEquiAngular, bool connectionCrossed,
                      double ownEquiAngularDensity, const MisSums* cameraSums, int cameraStride, const MisSums* lightSums,
                      int lightStride, double* perCount);

}  // namespace brume
