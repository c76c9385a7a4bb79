// Weighted expectation–maximisation of a von Mises–Fisher mixture (Banerjee et al. 2005;
// Herholz et al. 2016): fits a mixture to directions d_j with weights w_j ≥ 0, for guiding
// the weights are L_i(d_j) / p(d_j), importance samples of the incident radiance.
//   E step: γ_jk = π_k vMF_k(d_j) / Σ_l π_l vMF_l(d_j)
//   M step: π_k ∝ Σ_j w_j γ_jk;  r_k = Σ_j w_j γ_jk d_j;  μ_k = r_k / |r_k|;
//           r̄_k = |r_k| / Σ_j w_j γ_jk;  κ_k from the mean cosine r̄_k (vmfKappaForMeanCosine).
// The mean cosine of each lobe is shrunk towards a prior (r̄ ← (W r̄) / (W + w₀), w₀ a
// pseudo-weight of 1/8 of the lobe's share of the average), so a lobe that owns a
// handful of samples does not collapse onto them. Deterministic: the result depends only
// on the order of the samples.
#pragma once
#include <cstddef>

#include "brume/sampling/vmf.h"

namespace brume {

struct WeightedDirection {
    Vec3 d;
    float w;
};

// Fits up to `lobes` lobes (≤ VmfMixture::kMaxLobes) in `iterations` EM steps, starting
// from lobes spread evenly over the sphere. False if the weights sum to zero.
bool fitVmfMixture(const WeightedDirection* samples, size_t n, int lobes, int iterations, VmfMixture* out);

}  // namespace brume
