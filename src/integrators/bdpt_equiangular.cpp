#include "brume/integrators/bdpt_equiangular.h"

#include "brume/integrators/boundary_walk.h"
#include "brume/scene/camera_importance.h"

namespace brume {

EquiAngularAim equiAngularAim(const Scene& scene, const PathVertex& a, bool endsPath) {
    EquiAngularAim aim;
    aim.valid = true;
    aim.anchor = a.p;
    if (a.kind == VertexKind::Camera) {
        aim.toCamera = true;
    } else if (a.kind == VertexKind::Light || (endsPath && a.isSurface() && a.light >= 0)) {
        const Light& l = scene.lights()[a.light];
        if (l.atInfinity()) return EquiAngularAim{};
        if (!l.isPlanar()) aim.anchor = l.position;  // else the vertex: a point on the emitter
        aim.clip = &l;
    }
    return aim;
}

// The stand-in: equi-angular over [0, ∞) of the ray from prev's position, no clipping. It is
// positive wherever the sampler can place v (docs/mis.md), and needs no ray: from the light
// side the segment's far end is not part of the path. Exact: the segment the sampler would
// have had, found with a ray cast from prev to the first surface.
double equiAngularDensity(const Scene& scene, const PathVertex& prev, const PathVertex& v, const EquiAngularAim& aim,
                          MisSettings st) {
    Vec3 e = v.p - prev.p;
    float dist = length(e);
    if (!(dist > 0)) return 0.0;
    Vec3 d = e / dist;
    const float g = connectAnisotropy(st.connect, v.medium->g);
    if (!st.exactEquiAngular) return equiAngularStandInPdf(prev.p, d, aim.anchor, dist, g);
    // The walk's ray from prev, to the end of its first piece (where the sampler's segment ends).
    bool onSurface = prev.kind == VertexKind::Surface || (prev.kind == VertexKind::Light && dot(prev.ng, prev.ng) > 0);
    PathStats uncounted;
    BoundaryPiece first;
    BoundaryWalk(scene, leaving(prev.p, onSurface ? prev.ng : Vec3(0.0f), d), prev.media, uncounted).next(&first);
    const Vec3 o = prev.p;
    MediumSegment seg{o, d, first.t1, v.medium};
    EquiAngular ea;
    if (!equiAngularTowardsAim(scene, aim, seg, st.width, st.height, g, &ea)) return 0.0;
    return equiAngularPdf(ea, dist);
}

bool equiAngularTowardsAim(const Scene& scene, const EquiAngularAim& aim, const MediumSegment& seg, int width,
                           int height, float g, EquiAngular* out) {
    if (aim.clip) return equiAngularTowards(*aim.clip, aim.anchor, seg, g, out);
    float a = 0, b = seg.tEnd;
    // The camera as a point light: only the part of the ray inside the view frustum can
    // reach the film.
    if (aim.toCamera && !clipToFrustum(scene.camera(), width, height, seg.o, seg.d, &a, &b)) return false;
    *out = makeEquiAngular(seg.o, seg.d, aim.anchor, a, b, g);
    return true;
}

bool equiAngularVertex(const Scene& scene, const PathVertex& edge, const PathVertex& prev, Vec3 prevFrom,
                       const EquiAngularAim& aim, MisSettings mis, float u, PathVertex* out, double* density) {
    MediumSegment seg{edge.edgeOrigin, edge.edgeDir, edge.edgeEnd, edge.edgeMedium};
    EquiAngular ea;
    if (!equiAngularTowardsAim(scene, aim, seg, mis.width, mis.height, connectAnisotropy(mis.connect, edge.edgeMedium->g),
                               &ea))
        return false;
    float t = sampleEquiAngular(ea, u);
    float pea = equiAngularPdf(ea, t);
    if (!(pea > 0) || !std::isfinite(pea)) return false;
    const Medium& m = *edge.edgeMedium;
    PathVertex& v = *out;  // (out may be where the caller keeps edge's slot, not edge itself)
    v = PathVertex{};
    v.kind = VertexKind::Medium;
    v.medium = &m;
    v.media = edge.edgeMedia;
    v.p = seg.o + seg.d * t;
    v.beta = edge.edgeBeta * m.transmittance(Ray{seg.o, seg.d, seg.tEnd}, 0.0f, t) * m.sigmaSAt(v.p) / pea;
    Vec3 back = prev.p - v.p;
    float dist = length(back);
    if (!(dist > 0) || !isFinite(v.beta)) return false;
    v.wo = back / dist;
    v.edgeDist = dist;
    v.edgeOrigin = edge.edgeOrigin;
    v.edgeDir = edge.edgeDir;
    v.edgeEnd = edge.edgeEnd;
    v.edgeBeta = edge.edgeBeta;
    v.edgeMedium = edge.edgeMedium;
    v.edgeMedia = edge.edgeMedia;
    // The free-flight densities of the edge prev → v, as a walk along it would have them.
    MediumTransit tr = m.transit(Ray{prev.p, -v.wo, dist}, 0.0f, dist, prev.isMedium(), true);
    v.edgeFwdFreeFlight = tr.fwd;
    v.edgeRevFreeFlight = tr.rev;
    // Its density is the same in every channel: the subpath's channel ratios are prev's.
    v.channelRatio = prev.channelRatio;
    // pdfFwd: the equi-angular density of the point as the weights see it (the stand-in
    // unless exact): direction density × 1/d² × p_ea.
    *density = equiAngularDensity(scene, prev, v, aim, mis);
    // (prev's direction density is the camera walk's, guided, unless v is on a light walk's
    // ray: a camera connection's vertex, aimed at the camera.)
    const GuidingField* guide = aim.toCamera ? nullptr : mis.cameraGuide;
    v.pdfFwd = solidAngleToArea(v, v.wo, vertexDirectionPdf(scene, prev, prevFrom, -v.wo, mis.width, mis.height, guide),
                                dist) *
               *density;
    return v.pdfFwd[0] > 0;  // one density for every channel: the equi-angular one
}

}  // namespace brume
