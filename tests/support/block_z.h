// The worst |z| of block estimates (batch means with standard errors) against a reference
// per block, over blocks not skipped and all channels; the oracle tests' common check.
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "brume/math/vec3.h"
#include "support/pixel_estimates.h"

namespace brume::test {

// `reference(x, y)` gives block (x, y)'s value; `where` describes the worst block.
template <class Ref>
double worstZ(const std::vector<PixelEstimate>& px, int blocksWide, const std::vector<bool>& skip, Ref reference,
              std::string* where) {
    double worst = 0;
    for (size_t i = 0; i < px.size(); ++i) {
        if (skip[i]) continue;
        Vec3 ref = reference(int(i) % blocksWide, int(i) / blocksWide);
        for (int c = 0; c < 3; ++c) {
            double se = px[i].stderror(c), diff = std::abs(px[i].mean(c) - ref[c]);
            double z = se > 0 ? diff / se : (diff > 1e-5 * std::max(1.0, double(std::abs(ref[c]))) ? 1e9 : 0.0);
            if (z > worst) {
                worst = z;
                *where = "block (" + std::to_string(int(i) % blocksWide) + "," + std::to_string(int(i) / blocksWide) +
                         ") channel " + std::to_string(c) + ": " + std::to_string(px[i].mean(c)) + " ± " +
                         std::to_string(px[i].stderror(c)) + " vs " + std::to_string(ref[c]);
            }
        }
    }
    return worst;
}

}  // namespace brume::test
