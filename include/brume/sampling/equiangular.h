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
#pragma once
#include "brume/math/vec3.h"

namespace brume {

struct EquiAngular {
    double delta = 0;   // Δ: distance along the ray to the closest approach
    double D = 0;       // distance of c from the ray's line
    double a = 0, b = 0;
    double thetaA = 0, thetaB = 0;
    bool uniform = false;  // degenerate case: plain uniform sampling of [a, b]
};

// Set up for segment [a, b] (b may be +∞) of the ray o + t·d (d unit) towards point c.
// Falls back to uniform in t when the angle span is tiny (a short segment far away), and
// keeps D ≥ a small fraction of the scene scale so a light on the ray stays finite.
EquiAngular makeEquiAngular(Vec3 o, Vec3 d, Vec3 c, float a, float b);

// Distance for ξ ∈ [0, 1), clamped into [a, b].
float sampleEquiAngular(const EquiAngular& ea, float u);

// Density of t over [a, b]; 0 outside.
float equiAngularPdf(const EquiAngular& ea, float t);

// The density at t of equi-angular sampling over the unbounded ray [0, ∞) from o towards c,
// in float (θb − θa = π/2 + atan(Δ/D), a polynomial atan). Not for sampling: a fixed positive
// function of (o, d, c, t) that the bidirectional weights use as the stand-in density of an
// equi-angular vertex (docs/mis.md), 3–4× cheaper than makeEquiAngular + equiAngularPdf.
float equiAngularStandInPdf(Vec3 o, Vec3 d, Vec3 c, float t);

}  // namespace brume
