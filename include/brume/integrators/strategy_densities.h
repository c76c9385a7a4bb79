// The path tracer's four light-connection strategies in a medium (docs/path-tracer.md): A the
// connection at a free-flight vertex, B the emitter hit, C the equi-angular (or product)
// connection on a segment, D solid-angle distances towards an emissive triangle. Their
// densities for one path, and the power heuristic over them. Shared by the path tracer's
// weights (path_tracer.cpp) and the re-weighting that learns A's and C's shares
// (connection_shares.cpp), so the two cannot drift apart.
#pragma once
#include <cmath>

namespace brume {

// In double: at grazing angles a density can pass float's range, and its square long before.
struct StrategyDensities {
    double a = 0, b = 0, c = 0, d = 0;
};

// The power heuristic for the strategy with density `self` among all of p, as
// self²/Σ p_o², or 1/(1 + Σ_others (p_o/p_self)²) where that overflows: an infinite density
// of its own weighs 1 (and its estimate, divided by it, 0) instead of inf/inf.
inline double powerWeight(double self, const StrategyDensities& p) {
    if (!(self > 0)) return 0.0;
    if (std::isfinite(self)) {
        const double sum = p.a * p.a + p.b * p.b + p.c * p.c + p.d * p.d;
        if (std::isfinite(sum)) return self * self / sum;
    }
    double sum = 0;
    bool seenSelf = false;
    for (double o : {p.a, p.b, p.c, p.d}) {
        if (!seenSelf && o == self) {
            seenSelf = true;
            continue;
        }
        const double r = o / self;
        sum += std::isnan(r) ? 1.0 : r * r;
    }
    return 1.0 / (1.0 + sum);
}

}  // namespace brume
