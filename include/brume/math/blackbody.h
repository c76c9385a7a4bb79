// Blackbody emission as Blender Cycles 3.4's Principled Volume gives it (docs/scene-format.md,
// "blackbody"; measured in Cycles by tests/blender/measure_cycles.py):
//     e(T) = tint · (σ·10⁻⁶/π) · ((1 − b) + b·T⁴) · c(T)   [radiance per metre]
// σ = 5.670373e-8 W m⁻² K⁻⁴ (Stefan–Boltzmann), b the blackbody intensity, T in kelvin, and
// c(T) Planck's spectrum at T seen by the CIE 1931 2° observer, in linear Rec.709 and scaled to
// luminance 1:  c = M·(X, Y, Z)/Y,  (X, Y, Z) = ∫ B(λ, T)·(x̄, ȳ, z̄)(λ) dλ,  M: XYZ → Rec.709.
// The colour is held at its 800 K value below 800 K and its 12000 K value above 12000 K, as
// Cycles does. Where c leaves the Rec.709 gamut (blue below ≈ 1900 K, green below ≈ 960 K) a
// channel is negative, and Cycles' Principled Volume emits negative radiance there; brume
// keeps it too, so that a cool flame looks as in Cycles (the fire_grid round trip: clipped,
// its blue was 16 % brighter than Cycles'). Its Blackbody node clips to 0
// (blackbodyColourClipped). T ≤ 0 emits nothing (Cycles leaves (1 − b)·σ·10⁻⁶/π ≈ 1.8e-14
// per metre there).
#pragma once
#include "brume/math/vec3.h"

namespace brume {

// c(T): luminance-normalised Rec.709 colour of a blackbody (a channel may be negative).
Spectrum blackbodyColour(float kelvin);

// c(T) with negative channels set to 0, as Cycles' Blackbody node gives it.
Spectrum blackbodyColourClipped(float kelvin);

// e(T) for tint 1 and blackbody intensity b (the formula above).
Spectrum blackbodyEmission(float kelvin, float intensity);

}  // namespace brume
