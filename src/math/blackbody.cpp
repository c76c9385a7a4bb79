// Blackbody colour (math/blackbody.h): c(T) tabulated once, 2048 steps over [800 K, 12000 K]
// (5.5 K apart: linear interpolation is within 1e-4 of the integral), from Planck's law
// integrated against the CIE 1931 2° colour-matching functions at 5 nm, 380–780 nm.
#include "brume/math/blackbody.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace brume {

namespace {

// CIE 1931 2° standard observer x̄, ȳ, z̄ (CIE 15:2004, table T.4), 380–780 nm every 5 nm.
constexpr double kCie1931[81][3] = {
    {0.001368, 3.9e-05, 0.00645},  // 380
    {0.002236, 6.4e-05, 0.01055},
    {0.004243, 0.00012, 0.02005},
    {0.00765, 0.000217, 0.03621},
    {0.01431, 0.000396, 0.06785},
    {0.02319, 0.00064, 0.1102},
    {0.04351, 0.00121, 0.2074},
    {0.07763, 0.00218, 0.3713},
    {0.13438, 0.004, 0.6456},
    {0.21477, 0.0073, 1.03905},
    {0.2839, 0.0116, 1.3856},  // 430
    {0.3285, 0.01684, 1.62296},
    {0.34828, 0.023, 1.74706},
    {0.34806, 0.0298, 1.7826},
    {0.3362, 0.038, 1.77211},
    {0.3187, 0.048, 1.7441},
    {0.2908, 0.06, 1.6692},
    {0.2511, 0.0739, 1.5281},
    {0.19536, 0.09098, 1.28764},
    {0.1421, 0.1126, 1.0419},
    {0.09564, 0.13902, 0.81295},  // 480
    {0.05795, 0.1693, 0.6162},
    {0.03201, 0.20802, 0.46518},
    {0.0147, 0.2586, 0.3533},
    {0.0049, 0.323, 0.272},
    {0.0024, 0.4073, 0.2123},
    {0.0093, 0.503, 0.1582},
    {0.0291, 0.6082, 0.1117},
    {0.06327, 0.71, 0.07825},
    {0.1096, 0.7932, 0.05725},
    {0.1655, 0.862, 0.04216},  // 530
    {0.22575, 0.91485, 0.02984},
    {0.2904, 0.954, 0.0203},
    {0.3597, 0.9803, 0.0134},
    {0.43345, 0.99495, 0.00875},
    {0.51205, 1, 0.00575},
    {0.5945, 0.995, 0.0039},
    {0.6784, 0.9786, 0.00275},
    {0.7621, 0.952, 0.0021},
    {0.8425, 0.9154, 0.0018},
    {0.9163, 0.87, 0.00165},  // 580
    {0.9786, 0.8163, 0.0014},
    {1.0263, 0.757, 0.0011},
    {1.0567, 0.6949, 0.001},
    {1.0622, 0.631, 0.0008},
    {1.0456, 0.5668, 0.0006},
    {1.0026, 0.503, 0.00034},
    {0.9384, 0.4412, 0.00024},
    {0.85445, 0.381, 0.00019},
    {0.7514, 0.321, 0.0001},
    {0.6424, 0.265, 5e-05},  // 630
    {0.5419, 0.217, 3e-05},
    {0.4479, 0.175, 2e-05},
    {0.3608, 0.1382, 1e-05},
    {0.2835, 0.107, 0},
    {0.2187, 0.0816, 0},
    {0.1649, 0.061, 0},
    {0.1212, 0.04458, 0},
    {0.0874, 0.032, 0},
    {0.0636, 0.0232, 0},
    {0.04677, 0.017, 0},  // 680
    {0.0329, 0.01192, 0},
    {0.0227, 0.00821, 0},
    {0.01584, 0.005723, 0},
    {0.0113592, 0.004102, 0},
    {0.00811092, 0.002929, 0},
    {0.00579035, 0.002091, 0},
    {0.00410946, 0.001484, 0},
    {0.00289933, 0.001047, 0},
    {0.00204919, 0.00074, 0},
    {0.00143997, 0.00052, 0},  // 730
    {0.000999949, 0.0003611, 0},
    {0.000690079, 0.0002492, 0},
    {0.000476021, 0.0001719, 0},
    {0.000332301, 0.00012, 0},
    {0.000234826, 8.48e-05, 0},
    {0.000166151, 6e-05, 0},
    {0.000117413, 4.24e-05, 0},
    {8.30753e-05, 3e-05, 0},
    {5.87065e-05, 2.12e-05, 0},
    {4.15099e-05, 1.499e-05, 0},  // 780
};

constexpr float kMinKelvin = 800, kMaxKelvin = 12000;
constexpr int kSteps = 2048;

// XYZ → linear Rec.709 (sRGB primaries, D65 white).
Spectrum toRec709(double X, double Y, double Z) {
    return Spectrum(float(3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z),
                    float(-0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z),
                    float(0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z));
}

// Planck's B(λ, T) against the observer, normalised to Y = 1 (B's constant factor cancels).
Spectrum integratedColour(double T) {
    const double c2 = 1.4387769e-2;  // h·c/k, m·K
    double X = 0, Y = 0, Z = 0;
    for (int i = 0; i < 81; ++i) {
        const double lambda = (380.0 + 5.0 * i) * 1e-9;
        const double B = 1.0 / (std::pow(lambda, 5) * std::expm1(c2 / (lambda * T)));
        X += B * kCie1931[i][0];
        Y += B * kCie1931[i][1];
        Z += B * kCie1931[i][2];
    }
    return toRec709(X / Y, 1.0, Z / Y);
}

const std::array<Spectrum, kSteps + 1>& table() {
    static const std::array<Spectrum, kSteps + 1> t = [] {
        std::array<Spectrum, kSteps + 1> a;
        for (int i = 0; i <= kSteps; ++i) a[size_t(i)] = integratedColour(kMinKelvin + (kMaxKelvin - kMinKelvin) * i / double(kSteps));
        return a;
    }();
    return t;
}

}  // namespace

Spectrum blackbodyColour(float kelvin) {
    const float x = (std::clamp(kelvin, kMinKelvin, kMaxKelvin) - kMinKelvin) / (kMaxKelvin - kMinKelvin) * kSteps;
    const int i = std::min(int(x), kSteps - 1);
    const float f = x - float(i);
    const auto& t = table();
    return t[size_t(i)] * (1 - f) + t[size_t(i) + 1] * f;
}

Spectrum blackbodyColourClipped(float kelvin) {
    const Spectrum c = blackbodyColour(kelvin);
    return Spectrum(std::max(c.x, 0.0f), std::max(c.y, 0.0f), std::max(c.z, 0.0f));
}

Spectrum blackbodyEmission(float kelvin, float intensity) {
    if (!(kelvin > 0)) return Spectrum(0.0f);
    constexpr double kSigma = 5.670373e-8 * 1e-6 / 3.14159265358979323846;
    const double T2 = double(kelvin) * kelvin;
    return blackbodyColour(kelvin) * float(kSigma * ((1.0 - intensity) + intensity * T2 * T2));
}

}  // namespace brume
