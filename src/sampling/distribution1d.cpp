#include "brume/sampling/distribution1d.h"

#include <algorithm>

namespace brume {

Distribution1D::Distribution1D(const std::vector<float>& weights) {
    total_ = 0;
    for (float w : weights) total_ += std::max(0.0f, w);
    pmf_.resize(weights.size());
    cdf_.resize(weights.size());
    double acc = 0;
    for (size_t i = 0; i < weights.size(); ++i) {
        double p = total_ > 0 ? std::max(0.0f, weights[i]) / total_ : 0;
        pmf_[i] = float(p);
        acc += p;
        cdf_[i] = acc;
    }
}

int Distribution1D::sample(float u, float* prob) const {
    // First index whose cdf exceeds u; skip zero-probability entries at the end.
    int i = int(std::upper_bound(cdf_.begin(), cdf_.end(), double(u) * cdf_.back()) - cdf_.begin());
    i = std::min(i, int(pmf_.size()) - 1);
    while (i > 0 && pmf_[i] == 0) --i;
    *prob = pmf_[i];
    return i;
}

}  // namespace brume
