// Multiple importance sampling heuristics (Veach 1997, ch. 9).
#pragma once

namespace brume {

enum class MisHeuristic { Balance, Power };

// Power heuristic with β = 2 for one sample from each of two strategies: pa²/(pa² + pb²).
inline float powerHeuristic(float pa, float pb) {
    float a = pa * pa, b = pb * pb;
    return a + b > 0 ? a / (a + b) : 0.0f;
}

// r^β for a density ratio r: β = 2 (power) or 1 (balance).
inline double misPower(MisHeuristic h, double r) { return h == MisHeuristic::Power ? r * r : r; }
inline long double misPower(MisHeuristic h, long double r) { return h == MisHeuristic::Power ? r * r : r; }

}  // namespace brume
