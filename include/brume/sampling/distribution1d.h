// A discrete distribution proportional to non-negative weights (lights by power, emissive
// triangles by power). sample() returns an index and its probability.
#pragma once
#include <vector>

namespace brume {

class Distribution1D {
public:
    Distribution1D() = default;
    explicit Distribution1D(const std::vector<float>& weights);
    bool empty() const { return total_ <= 0; }
    int size() const { return int(pmf_.size()); }
    // u in [0,1): returns index i with probability pmf(i).
    int sample(float u, float* prob) const;
    float pmf(int i) const { return pmf_[i]; }
    double total() const { return total_; }

private:
    std::vector<double> cdf_;  // cdf_[i] = sum of pmf over [0, i]
    std::vector<float> pmf_;
    double total_ = 0;
};

}  // namespace brume
