// Importance of the pinhole camera, so that light-subpath vertices can be connected to the
// camera and splatted to the film (light tracing, the t = 1 strategies of a bidirectional
// path tracer), and clipping of rays to the view frustum.
//
// Geometry (pbrt-v3's pinhole, in brume's conventions). The film is the rectangle of the
// plane at distance 1 in front of the camera with half-extents
//     tanY = tan(yfov / 2),   tanX = tanY · width / height
// (the image's width/height ratio, as in Camera::generateRay; Camera::aspectRatio is not
// used), and area A = 4 · tanX · tanY. Film position (fx, fy) in pixels, top-left origin,
// corresponds to the point forward + right · sx + up · sy of that plane with
//     sx = (2 fx / width − 1) · tanX,   sy = (1 − 2 fy / height) · tanY.
// The film is the half-open pixel rectangle [0, width) × [0, height), the same rule as
// SplatList::splat, so every accepted connection lands on a pixel.
//
// For a unit direction w leaving the camera, with cosθ = dot(w, forward) > 0, that lands on
// the film:
//     We(w)     = 1 / (A · cos⁴θ)   importance,
//     pdfDir(w) = 1 / (A · cos³θ)   solid-angle density of generateRay's direction when the
//                                   film position is uniform over the whole film
// (a film area element dx·dy on the plane at distance 1 subtends dω = cos³θ dx dy). Hence
// ∫film We cosθ dω = ∫film pdfDir dω = 1, and We(w) · cosθ = pdfDir(w).
//
// Normalisation of light tracing (what the bidirectional integrator relies on).
// The camera tracer's pixel value is the mean, over uniform film positions inside pixel j
// (a unit square in pixel units), of the radiance L arriving along the primary ray. With
// N = width · height pixels, a uniform film position over the whole film has density 1/N per
// pixel², i.e. pdfDir(w) per steradian, so
//     I_j = N · ∫Ω 1_j(w) · pdfDir(w) · L(w) dω = N · ∫Ω 1_j(w) · We(w) · cosθ · L(w) dω,
// where 1_j(w) says whether w lands in pixel j. For the scene point x seen along w at
// distance d (surface normal n_x), dω = |cos_x| / d² dA(x), cos_x = dot(n_x, wi), so
//     I_j = N · ∫A 1_j · L(x → camera) · We(−wi) · cosθ · |cos_x| / d² · V dA(x).
// A light subpath whose vertex x carries the Monte Carlo weight β of the radiance leaving x
// towards the camera (for a vertex on the light itself: Le / p_A(x), p_A the area density
// with which x was sampled; for a scattering vertex: the path throughput times the BSDF or
// phase function value for (incoming, wi)) contributes
//     C = β · We(−wi) · cosθ / d² · |cos_x| · (visibility / transmittance to the camera)
// (|cos_x| is 1 for a vertex in a medium) at the film position (fx, fy) of the connection,
// and the estimate of pixel j from N_L light subpaths is
//     I_j ≈ (N / N_L) · Σ { C over the subpaths that land in pixel j }.
// The Film divides splats by its number of passes. If every pass traces exactly one light
// subpath per pixel (N_L = N · passes), the splat value is C itself; if a pass traces M light
// subpaths, splat C · N / M.
// Example (tested): a Lambertian emitter of radiance L filling the view, points sampled
// uniformly on it (p_A = 1 / area), gives C = L · area · We · cosθ · cos_x / d², and every
// pixel converges to L.
//
// The camera position is a delta in area: pdf = 1, and We already includes the whole camera
// response. For MIS, the density with which the camera would have generated the light
// vertex x, per unit area at x, is pdfDir(−wi) · |cos_x| / d².
#pragma once
#include "brume/scene/camera.h"

namespace brume {

struct CameraConnection {
    Vec3 wi;               // unit direction from the reference point towards the camera position
    float dist = 0;        // distance to the camera
    float fx = 0, fy = 0;  // film position in pixels (top-left origin), as in Camera::generateRay
    float We = 0;          // importance for the direction −wi leaving the camera
    float pdf = 1;         // the camera position is a delta: 1
};

// For a point `ref` in the scene: the film position it projects to, if it lies in front of the
// camera and inside the film [0, width) × [0, height); false otherwise (out untouched).
// Visibility is not tested.
bool connectToCamera(const Camera& cam, Vec3 ref, int width, int height, CameraConnection* out);

// Importance We(w) and direction density pdfDir(w) of a ray leaving the camera in direction w
// (0 when w does not land on the film). w need not be unit length: the film position depends
// only on its direction (so connectToCamera(cam, cam.position + v) and cameraImportance(cam, v)
// accept exactly the same vectors v).
float cameraImportance(const Camera& cam, Vec3 w, int width, int height);
float cameraPdfDir(const Camera& cam, Vec3 w, int width, int height);

// The part of the ray o + t·d with t in [*t0, *t1] whose points project inside the film (the
// view frustum: four planes through the camera position, which also bound it to the half-space
// in front of the camera). d need not be unit length; *t1 may be +∞ (the result then may be
// too). Returns false, leaving *t0 and *t1 unchanged, if the part is empty or a single point.
// The interval is widened by a bound on the float rounding of o + t·d and of the projection,
// so that every point connectToCamera accepts is kept: the result may be a superset only by
// rounding, and it never leaves the input interval.
bool clipToFrustum(const Camera& cam, int width, int height, Vec3 o, Vec3 d, float* t0, float* t1);

}  // namespace brume
