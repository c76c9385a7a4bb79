// Equi-angular connection vertices of the bidirectional tracer (docs/mis.md): what a
// connection aims at, the vertex that the equi-angular variant of a strategy places on its
// walk's ray towards the other subpath (the camera vertex z(t−1) towards y(s−1); for camera
// connections the light vertex y(s−1) towards the pinhole), and that vertex's density as the
// MIS weights see it.
#pragma once
#include "brume/integrators/bdpt_mis.h"
#include "brume/integrators/equiangular_segment.h"

namespace brume {

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

// Equi-angular sampling on seg towards the aim, clipped as the aim says; false if nothing of
// seg remains. g ≠ 0: product sampling (connectAnisotropy). For a camera connection the
// phase is the light vertex's, between its incoming direction (seg.d) and the pinhole.
bool equiAngularTowardsAim(const Scene& scene, const EquiAngularAim& aim, const MediumSegment& seg, int width,
                           int height, float g, EquiAngular* out);

// The equi-angular density (per unit length) with which medium vertex v is placed on the ray
// from prev aimed at `aim`, as the weights use it (stand-in or exact, by settings).
double equiAngularDensity(const Scene& scene, const PathVertex& prev, const PathVertex& v, const EquiAngularAim& aim,
                          MisSettings settings);

// The equi-angular variant of the vertex after prev: a point on the ray its walk traced from
// prev (whatever free flight made of that ray: a medium point, a surface, or nothing), within
// the ray's first medium, sampled towards `aim` with the number u. `edge` is the vertex whose
// edge record (PathVertex::edge*) holds that ray; prevFrom is the direction from prev back
// along its own subpath. False if no point can be placed (*out may then have been written).
// out must not be edge or prev.
// *density receives the vertex's equi-angular density as the weights see it.
bool equiAngularVertex(const Scene& scene, const PathVertex& edge, const PathVertex& prev, Vec3 prevFrom,
                       const EquiAngularAim& aim, MisSettings settings, float u, PathVertex* out, double* density);

}  // namespace brume
