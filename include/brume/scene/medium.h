// A homogeneous participating medium: coefficients in 1/m, Henyey–Greenstein anisotropy g.
#pragma once
#include <string>
#include "brume/math/vec3.h"

namespace brume {

struct Medium {
    std::string name;
    Spectrum sigmaS;  // scattering
    Spectrum sigmaA;  // absorption
    float g = 0;      // HG anisotropy, (−1, 1)
    Spectrum sigmaT() const { return sigmaS + sigmaA; }
};

}  // namespace brume
