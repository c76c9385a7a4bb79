#include "brume/guiding/vmf_fit.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace brume {

namespace {

// Starting axes: a Fibonacci spiral of n points, evenly spread.
Vec3 spiral(int i, int n) {
    const float z = 1.0f - (2.0f * float(i) + 1.0f) / float(n);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = float(i) * 2.39996323f;  // the golden angle
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

constexpr float kMaxKappa = 1000.0f;

struct Sum3 {
    double x = 0, y = 0, z = 0;
};

}  // namespace

bool fitVmfMixture(const WeightedDirection* samples, size_t n, int lobes, int iterations, VmfMixture* out) {
    double total = 0;
    for (size_t j = 0; j < n; ++j) total += samples[j].w;
    if (!(total > 0) || !std::isfinite(total)) return false;
    lobes = std::clamp(lobes, 1, VmfMixture::kMaxLobes);
    VmfMixture m;
    m.count = lobes;
    for (int k = 0; k < lobes; ++k) {
        m.weight[k] = 1.0f / float(lobes);
        m.lobe[k].mu = spiral(k, lobes);
        m.lobe[k].kappa = 3.0f;
    }
    double gamma[VmfMixture::kMaxLobes];
    double scale[VmfMixture::kMaxLobes];  // vMF(d) = scale · e^{κ(μ·d − 1)} (vmf.h)
    for (int it = 0; it < iterations; ++it) {
        double W[VmfMixture::kMaxLobes] = {};
        Sum3 R[VmfMixture::kMaxLobes];
        for (int k = 0; k < lobes; ++k) scale[k] = vmfScale(m.lobe[k].kappa);
        for (size_t j = 0; j < n; ++j) {
            const WeightedDirection& s = samples[j];
            if (!(s.w > 0)) continue;
            double sum = 0;
            for (int k = 0; k < lobes; ++k)
                sum += gamma[k] = double(m.weight[k]) *
                                  scale[k] * std::exp(m.lobe[k].kappa * (double(dot(m.lobe[k].mu, s.d)) - 1.0));
            if (!(sum > 0)) continue;
            for (int k = 0; k < lobes; ++k) {
                const double r = s.w * gamma[k] / sum;
                W[k] += r;
                R[k].x += r * s.d.x;
                R[k].y += r * s.d.y;
                R[k].z += r * s.d.z;
            }
        }
        double wSum = 0;
        for (int k = 0; k < lobes; ++k) wSum += W[k];
        size_t used = 0;
        for (size_t j = 0; j < n; ++j) used += samples[j].w > 0;
        if (!(wSum > 0)) return false;
        for (int k = 0; k < lobes; ++k) {
            m.weight[k] = float(W[k] / wSum);
            const double len = std::sqrt(R[k].x * R[k].x + R[k].y * R[k].y + R[k].z * R[k].z);
            if (!(W[k] > 0) || !(len > 0)) {
                m.lobe[k].kappa = 0;
                continue;
            }
            m.lobe[k].mu = Vec3(float(R[k].x / len), float(R[k].y / len), float(R[k].z / len));
            const double prior = 2.0 * wSum / double(used);
            const double rBar = len / (W[k] + prior);
            m.lobe[k].kappa = std::min(kMaxKappa, vmfKappaForMeanCosine(float(rBar)));
        }
    }
    m.prepare();
    *out = m;
    return true;
}

}  // namespace brume
