// Next-event estimation towards emissive media (scene/volume_lights.h): from a scattering
// vertex x, a point y drawn by the media's emitted power, joined by a shadow ray through every
// medium in between (ratio tracking in grids). The path tracer uses it at every vertex that
// is not specular, MIS-combined with the emission its next ray gathers (medium_emission.cpp).
// Both make the path x → y; in volume measure at y their densities are
//     next-event:  p_n(y) = P(medium)·P(brick)/V_brick          (VolumeLights::pdf)
//     gathering:   p_g(y) = p_dir(ω) / (ℓ·t²)
// (the direction's density at x, then y's point uniform over the length ℓ of its stratum of
// the ray's interval in y's brick, t = |y − x|), and each is weighted by the power heuristic. Close to x
// p_g grows as 1/t² and takes the weight (next-event estimation's 1/t² there has infinite
// variance); far from it, at a small bright source, p_n does.
#pragma once
#include <cmath>

#include "brume/integrators/boundary_walk.h"
#include "brume/integrators/integrator.h"
#include "brume/integrators/sample_dimensions.h"

namespace brume {

struct VolumeLightConnection {
    Vec3 wi;      // unit, x → y
    Spectrum Le;  // e(y)·T(x, y) / (|x − y|²·p_n(y)): times the phase function or BSDF·|cos|, the estimate
    float pdf = 0;          // p_n(y)
    float dist = 0;         // t
    float stratumLength = 0;  // ℓ
};

// The power heuristic's weight for next-event estimation (own = true) or the gathering, from
// p_n, the direction's density p_dir at x, ℓ and t.
inline float volumeLightWeight(bool own, double pn, double pdir, double stratumLength, double t) {
    const double pg = pdir / (stratumLength * t * t);
    const double a = own ? pn * pn : pg * pg, b = own ? pg * pg : pn * pn;
    return a + b > 0 && std::isfinite(a + b) ? float(a / (a + b)) : (own ? 0.0f : 1.0f);
}

// The gathering's weight on each point of medium `medium`'s estimate (Medium::emitted) along a
// ray whose direction density at its start was dirPdf.
inline Medium::PointWeight gatheringWeight(const Scene& scene, int medium, float dirPdf) {
    return [&scene, medium, dirPdf](float t, size_t brick, float length) {
        return volumeLightWeight(false, scene.volumeLights().pdf(medium, brick), dirPdf, length, t);
    };
}

// x: a surface point with geometric normal ng, or a medium point (ng = 0), in `media`.
// Numbers: dims + kPick (medium and brick), kLightPoint (2D) and kAnchor (the point in the
// brick). False if nothing arrives: y blocked, outside its medium's bounding mesh, or dark.
bool connectVolumeLight(const Scene& scene, Vec3 x, Vec3 ng, const MediumStack& media, const Sampler& sampler,
                        uint32_t dims, PathStats& stats, VolumeLightConnection* out);

}  // namespace brume
