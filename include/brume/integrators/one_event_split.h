// The bidirectional tracer in single scattering, where it can be that cheap: the camera
// family's paths made by the path tracer itself, and light tracing's, split between them by
// one weight per path (docs/mis.md, "One scattering event: two families").
//
// Why. In single scattering (--max-depth 1) beside point, spot and sphere lights in
// homogeneous grey fog, a path camera c → x (in the medium) → light point y is made by two
// families:
//   camera: the camera ray through x, x placed on it equi-angularly towards y (the path
//           tracer's strategy C, product sampling where it takes the phase; the walk passes
//           through the medium there, so C stands alone), or with --connect density by free
//           flight, and y the light;
//   light:  light tracing: a ray from y through x, x placed on it by free flight and (unless
//           --connect density) equi-angularly towards the pinhole (the camera as a point
//           light), power-weighted between the two, then connected to the camera;
// every other strategy of the tracer (general connections, emitter hits) makes none of them.
// The generic tracer builds both subpaths' vertex records and weighs every connection over
// all strategies; in single scattering that machinery cost 1.6x the path tracer's time for
// the same rays (val_thin_lamp, 128 spp), and with the light subpaths 1.9x. Here the camera
// family is the path tracer's sample, and the only weight it needs is its family's share.
// (Light tracing by equi-angular sampling alone cost less, but the fog room's error with it was
// 1.5x that with free flight beside it, docs/results.md.)
//
// The weight. Per unit volume at x, for a light picked with pmf P_C by the camera family
// (along the camera ray, light_selection.h) and P_L by light tracing (power), and a pinhole
// whose film is sampled uniformly (camera_importance.h's pdfDir) but around the light's
// image, where the renderer draws it by inverse distance (m, light_pixels.h):
//   p_C = P_C · pdfDir(ω_cx) · m / |x − c|² · π_C,     π_C per unit length on the camera ray
//   p_L = q · P_L · p_e(ω_yx) / |x − y|² · π_L,    π_L on the light ray (p_e: emission direction
//                                                density; q: light subpaths made per sample)
// The power heuristic over the two, with light tracing's variance-aware factor κ
// (direct_light_tracing.h), gives the families
//   W_C = p_C² / (p_C² + κ²·p_L²),   W_L = 1 − W_C.
// A camera-family sample counts the path tracer's value times W_C; a light-family sample its
// value times W_L and 1/q. The weights sum to 1 on every path, so the sum is unbiased whatever
// π_C and π_L are; they are chosen to be near the densities the families sample with, and cheap
// where the path tracer asks (once per connection): π_C is the path tracer's own density (on
// the light side found again with one ray along the camera ray to its first surface), and
// Σ π_L² that of free flight and the equi-angular stand-in over [0, ∞) (equiangular.h), which
// need no ray.
// Paths whose x is on a surface are the camera family's alone (W_C = 1: light tracing here
// makes none of them).
//
// Sphere lights. There y is a point on the sphere, made by both families with a density per
// unit area of its own: by the camera family's next-event estimation at x (solid angle p_A,
// or B's phase function p_B when a phase-sampled ray hits the sphere), by light tracing
// uniformly over the surface (pdfPos), then cosine-distributed (p_e). So
//   p_C = P_C · pdfDir(ω_cx) · m / |x − c|² · π_C · (p_A + p_B)(ω_xy) · |cos θ_y| / |x − y|²
//   p_L = q · P_L · pdfPos · p_e(ω_yx) / |x − y|² · π_L
// and every camera-family value of such a path (A, B and C alike) takes W_C of the same
// path: π_C is then C's equi-angular density towards the centre (cameraDensityOn) whichever
// of the path tracer's strategies placed x, so that the families' weights still sum to one
// on every path. Light tracing's value carries the cosine at y (Le·|cos θ_y| / (pdfPos·p_e)).
// The walk makes no vertex past x in single scattering, so no path reaches the sphere through
// a specular surface.
#pragma once
#include "brume/integrators/integrator.h"
#include "brume/integrators/path_tracer.h"
#include "brume/scene/light.h"
#include "brume/scene/light_pixels.h"
#include "brume/scene/medium.h"

namespace brume {

class DirectLightTracing;
struct MediumSegment;
class SplatList;
struct PathStats;
class Sampler;

// Whether single scattering in `scene` is made by the two families above: every light a
// point, spot or sphere light, media (if any) only the ambient one, homogeneous, grey and not
// emissive, nothing transparent that emits.
bool oneEventSplitApplies(const Scene& scene);

struct OneEventSplit {
    ConnectMode mode = ConnectMode::Mis;
    int width = 0, height = 0;
    double q = 1;      // light subpaths made per sample
    double kappa = 1;  // light tracing's variance-aware factor
    // Where the renderer draws film positions by inverse distance (null: nowhere).
    const LightPixels* lightPixels = nullptr;
    // Learning and checking passes of κ (direct_light_tracing.h): where the camera family's
    // value of this sample, weighted within its family alone, is summed.
    Spectrum* cameraAlone = nullptr;
    // The check's passes (direct_light_tracing.h, whether light tracing pays): where the camera
    // family's weighted value is summed instead of returned; the film then takes the camera
    // side alone (W_C = 1), and light tracing's weighted splats are measured, not splatted.
    Spectrum* cameraSplit = nullptr;

    // W_C of the path camera → x (in medium m) → point y of light `li`, the camera family's
    // density of x per unit length on its ray being `cameraDensity`.
    float cameraWeight(const Scene& scene, Vec3 x, const Medium& m, int li, Vec3 y, double cameraDensity) const;
    // The same for a camera-family sample, whose x lies on the camera ray set by atCameraRay:
    // the film's part of p_C (pdfDir · m) and the light pick's ratio are the ray's, so they are
    // taken once per sample, not found again from x at each connection (a projection onto the
    // film and a lookup of m: about 1 % of the forward fog's time).
    float cameraFamilyWeight(const Scene& scene, Vec3 x, const Medium& m, int li, Vec3 y, double cameraDensity) const;
    // The camera family's ray through film position (fx, fy) (before the path tracer's sample).
    void atCameraRay(float fx, float fy) {
        rayFx_ = fx;
        rayFy_ = fy;
        rayFilm_ = -1;
        pickLight_ = -1;
    }
    // That density as the path tracer has it: equi-angular (product) towards the light's
    // position over the camera ray's segment to its first surface, clipped to the light (one
    // ray), or free flight (no ray). (The light's point is not needed: a point or spot light's
    // is its position, and C aims at a sphere's centre.)
    double cameraDensity(const Scene& scene, Vec3 x, const Medium& m, const Light& light, PathStats& stats) const;
    // The same at distance t on that segment, known (the camera family's own segment): towards
    // the light's position (a sphere's centre, where the path tracer's strategy C aims).
    double cameraDensityOn(const Light& light, const MediumSegment& seg, float t) const;
    // A camera-family value of such a path and its W_C: summed alone while learning, returned
    // weighted.
    Spectrum share(const Spectrum& value, float weight) const {
        if (cameraAlone) *cameraAlone += value;
        if (cameraSplit) {
            *cameraSplit += value * weight;
            return value;
        }
        return value * weight;
    }

private:
    // W_C from p_C for light `li`'s point y, the path ending at x.
    float weightFrom(const Scene& scene, Vec3 x, const Medium& m, int li, Vec3 y, double pc) const;
    // The ray's light pick ratio (as cameraWeight's `pick`), for its last light.
    double rayPick(const Scene& scene, Vec3 dir, int li) const;
    float rayFx_ = 0, rayFy_ = 0;
    mutable double rayFilm_ = -1;  // 1/A · m of the camera family's ray (−1: not yet taken)
    mutable int pickLight_ = -1;   // the light whose ratio rayPickValue_ holds
    mutable double rayPickValue_ = 1;
};

// The light family of one sample (made with probability q by the caller): a light, an
// emission from it, x on its ray, connected to the camera and splatted with its weight.
// `learning`: also its value alone, counted 1/q (κ's learning and checking passes; every splat
// then made).
void oneEventLightTracing(const Scene& scene, const OneEventSplit& split, const Sampler& lightSampler, PathStats& stats,
                          SplatList& splats, DirectLightTracing* learning);

}  // namespace brume
