// Multiple importance sampling heuristics (Veach 1997, ch. 9).
#pragma once

namespace brume {

// Power heuristic with β = 2 for one sample from each of two strategies: pa²/(pa² + pb²).
inline float powerHeuristic(float pa, float pb) {
    float a = pa * pa, b = pb * pb;
    return a + b > 0 ? a / (a + b) : 0.0f;
}

}  // namespace brume
