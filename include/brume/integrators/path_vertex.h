// A vertex of a camera or light subpath (bidirectional methods). Densities are in area
// measure at the vertex, with no cosine at medium vertices, and include the free-flight
// density of the event that made the vertex: σt·T for a scattering point in a medium, the
// pass probability T for a surface beyond a medium. They are kept per colour channel: the
// walks sample distances with one (hero) channel, and the weights are taken over channels
// too (bdpt_mis.h). pdfFwd is for the subpath's own direction; pdfRev for the reverse, i.e.
// the density with which the other subpath's walk would have made this vertex.
#pragma once
#include "brume/guiding/guiding_field.h"
#include "brume/math/vec3.h"
#include "brume/scene/bsdf.h"
#include "brume/scene/scene.h"

namespace brume {

enum class VertexKind : unsigned char { Camera, Light, Surface, Medium };

struct PathVertex {
    VertexKind kind = VertexKind::Surface;
    bool delta = false;      // specular surface: no connection can be made at this vertex
    bool deltaLight = false; // light vertex of a point, spot or directional light: no path can hit it
    Vec3 p;
    Vec3 ng, ns;             // surface: geometric (front side) and shading normal; light: emitting normal
    Vec3 wo;                 // unit, towards the previous vertex of its subpath
    float u = 0, v = 0;      // surface texture coordinates
    int mesh = -1, triangle = -1;
    int light = -1;          // light vertex, or a surface vertex on an emitter (index into lights())
    const Medium* medium = nullptr;  // medium vertex
    MediumStack media;       // the media where the vertex was reached (the incoming side of a surface)
    Spectrum beta{1.0f};     // subpath throughput up to and including this vertex
    // Densities in double: products of free-flight densities over long edges leave float's range.
    Channels pdfFwd{0.0};    // area density of making this vertex from the previous one
    Channels pdfRev{0.0};    // area density of making it from the next one
    // The edge from the previous vertex to this one: its length and the free-flight density
    // of the reverse walk's event at the previous vertex (see random_walk.cpp).
    float edgeDist = 0;
    Channels edgeFwdFreeFlight;
    Channels edgeRevFreeFlight;
    // The walk's ray for that edge, for the equi-angular variant of a medium vertex: its origin,
    // the distance along it to the surface ending the medium, the throughput at its start, and
    // whether it crossed an invisible boundary (then there is no such variant).
    Vec3 edgeOrigin, edgeDir;
    float edgeEnd = 0;
    Spectrum edgeBeta{0.0f};
    bool edgeCrossed = false;
    // What the ray gathered from emissive media (camera walks, free_flight_walk.h), times the
    // throughput at its start and its channel weight: the ray's whole share of the image.
    Spectrum edgeEmission{0.0f};
    const Medium* edgeMedium = nullptr;  // the medium the ray starts in (null: vacuum)
    MediumStack edgeMedia;               // the media at the ray's start
    // The walk traced this ray but made no vertex on it (it escaped): only the edge fields
    // above are set, so that an equi-angular vertex can still be placed on the ray.
    bool ghost = false;
    // The MIS partial sums of the subpath up to this vertex (bdpt_mis.h, misPrefixes): kept in
    // the vertex, as SmallVCM keeps its, so a stored subpath carries what its weights need.
    // Without coloured media one sum (double); with them one per channel, as its natural
    // logarithm (the sums leave double's range).
    double misPrefixGrey = 0, misVariantGrey = 1;
    Channels misPrefix{0.0};
    Channels misVariant{0.0};
    // Π over this subpath's vertices up to this one of edgeFwdFreeFlight_c / _h (h: the
    // sample's hero channel): the subpath's density in channel c relative to the hero's.
    Channels channelRatio;

    bool isSurface() const { return kind == VertexKind::Surface; }
    bool isMedium() const { return kind == VertexKind::Medium; }
};

// Solid-angle density at another vertex → area density at `to`, a distance d away in unit
// direction w (seen from `to`): |cos| at a surface or area-light vertex, none in a medium or
// at a point.
inline double solidAngleToArea(const PathVertex& to, Vec3 w, double pdfDir, double d) {
    double g = 1.0 / (d * d);
    if (to.kind == VertexKind::Surface || (to.kind == VertexKind::Light && dot(to.ng, to.ng) > 0))
        g *= std::abs(dot(to.ng, w));
    return pdfDir * g;
}

}  // namespace brume

namespace brume {

// Solid-angle density with which vertex v, reached from direction wFrom (unit, pointing away
// from v towards where its path came from), continues in direction wTo: camera, emission,
// phase function or BSDF (0 for a specular surface and for sphere lights, which end paths).
// guide: the density is the camera walk's and that walk is guided (`--guiding on`,
// docs/path-guiding.md): at medium and non-specular surface vertices the guided mixture
//   α · p_guide(wTo) + (1 − α) · p_phase/bsdf(wTo)   (guided_phase.h)
// with α the share of the cell at v.p. The light walk is never guided: its densities, and
// every density of a walk without guiding, pass null.
float vertexDirectionPdf(const Scene& scene, const PathVertex& v, Vec3 wFrom, Vec3 wTo, int width, int height,
                         const GuidingField* guide = nullptr);

// The BSDF of a surface vertex (base colour texture applied).
inline Bsdf vertexBsdf(const Scene& scene, const PathVertex& v) { return scene.surfaceBsdf(v.mesh, v.u, v.v, v.ng, v.ns); }

}  // namespace brume
