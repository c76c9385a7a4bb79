// Multiple importance sampling heuristics (Veach 1997, ch. 9).
#pragma once

namespace brume {

// Cube (β = 3) weights nothing: the efficiency-aware tracer's statistics read the sums Σ_k
// (n_k p_k)³ of a path through it (allocation_statistics.h).
enum class MisHeuristic { Balance, Power, Cube };

// Power heuristic with β = 2 for one sample from each of two strategies: pa²/(pa² + pb²).
inline float powerHeuristic(float pa, float pb) {
    float a = pa * pa, b = pb * pb;
    return a + b > 0 ? a / (a + b) : 0.0f;
}

// r^β for a density ratio r: β = 2 (power), 1 (balance) or 3 (cube).
inline double misPower(MisHeuristic h, double r) { return h == MisHeuristic::Power ? r * r : h == MisHeuristic::Balance ? r : r * r * r; }
inline long double misPower(MisHeuristic h, long double r) {
    return h == MisHeuristic::Power ? r * r : h == MisHeuristic::Balance ? r : r * r * r;
}

}  // namespace brume
