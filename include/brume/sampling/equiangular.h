// Equi-angular sampling (Kulla & Fajardo 2012): a distance t on the segment [a, b] of the ray
// o + t·d with density proportional to 1/r², r the distance to a point c.
//
// With Δ = (c − o)·d the closest approach along the ray and D the distance from c to the
// line, r² = D² + (t − Δ)². Writing t − Δ = D·tanθ, dt = D/cos²θ dθ, so
//   ∫ dt / (D² + (t−Δ)²) = θ / D,
// and the normalised density over [a, b] is
//   pdf(t) = D / ((θb − θa)(D² + (t − Δ)²)),   θx = atan((x − Δ)/D),
// sampled by t = Δ + D·tan((1−ξ)θa + ξθb). The angles θ run over (−π/2, π/2): an unbounded
// segment has θb = π/2. Computed in double: near θ = ±π/2 the tangent amplifies rounding.
//
// Product sampling (equi-angular × phase): with a Henyey–Greenstein g ≠ 0, the angle is drawn
// from a mixture of the uniform angle above and the phase part of hg_angle.h (the phase at
// x(t) between d and the direction to c, which is a function of the angle alone): one number
// picks the part and, rescaled, samples it, the uniform part forwards along the ray and the
// phase part backwards, so that the map from ξ to t has no jump (equiangular.cpp). The density
// is exact: pdf(t) = (α/(θb − θa) + (1 − α)·q(θ(t))) · D/(D² + (t − Δ)²). g = 0 is the plain
// sampler, and costs nothing more.
#pragma once
#include "brume/math/vec3.h"
#include "brume/sampling/hg_angle.h"

namespace brume {

struct EquiAngular {
    double delta = 0;   // Δ: distance along the ray to the closest approach
    double D = 0;       // distance of c from the ray's line
    double a = 0, b = 0;
    double thetaA = 0, thetaB = 0;
    bool uniform = false;  // degenerate case: plain uniform sampling of [a, b]
    HgAngle phase;         // product sampling's phase part (phase.alpha = 1: none)
};

// Set up for segment [a, b] (b may be +∞) of the ray o + t·d (d unit) towards point c.
// Falls back to uniform in t when the angle span is tiny (a short segment far away), and
// keeps D ≥ a small fraction of the scene scale so a light on the ray stays finite.
// g ≠ 0: product sampling with the phase of that anisotropy (the scattering angle at x(t)
// between d and the direction to c).
EquiAngular makeEquiAngular(Vec3 o, Vec3 d, Vec3 c, float a, float b, float g = 0.0f);

// Distance for ξ ∈ [0, 1), clamped into [a, b].
float sampleEquiAngular(const EquiAngular& ea, float u);

// Density of t over [a, b]; 0 outside.
float equiAngularPdf(const EquiAngular& ea, float t);

// The density at t of equi-angular sampling over the unbounded ray [0, ∞) from o towards c,
// in float (θb − θa = π/2 + atan(Δ/D), a polynomial atan). Not for sampling: a fixed positive
// function of (o, d, c, t) that the bidirectional weights use as the stand-in density of an
// equi-angular vertex (docs/mis.md), 3–4× cheaper than makeEquiAngular + equiAngularPdf.
// g ≠ 0: the product sampler's density over [0, ∞) instead (in double, as makeEquiAngular).
float equiAngularStandInPdf(Vec3 o, Vec3 d, Vec3 c, float t, float g = 0.0f);

}  // namespace brume
