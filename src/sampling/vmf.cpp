#include "brume/sampling/vmf.h"

#include <algorithm>
#include <cmath>

#include "brume/math/frame.h"

namespace brume {

namespace {
constexpr double kLog4Pi = 2.5310242469692907;  // log(4π)
}

// log(κ / (4π sinh κ)) = log κ − log 2π − κ − log(1 − e^{−2κ}).
double vmfLogNorm(double kappa) {
    if (kappa < 1e-4) return -kLog4Pi - kappa * kappa / 6.0;  // κ/sinh κ ≈ 1 − κ²/6
    constexpr double kLog2Pi = 1.8378770664093453;
    // Beyond κ = 20, log(1 − e^{−2κ}) < 5e−18: below double's resolution of the rest.
    return std::log(kappa) - kLog2Pi - kappa - (kappa < 20.0 ? std::log1p(-std::exp(-2.0 * kappa)) : 0.0);
}

// C(κ) e^{κ(μ·w)} written as C(κ) e^{κ} · e^{κ(μ·w − 1)}: no overflow for large κ.
float vmfPdf(const VmfLobe& lobe, Vec3 w) {
    const double k = lobe.kappa;
    if (k < 1e-4) return float(1.0 / (4.0 * M_PI));
    const double c = dot(lobe.mu, w);
    return float(std::exp(vmfLogNorm(k) + k + k * (std::min(c, 1.0) - 1.0)));
}

// Inverting the cdf of μ·w = c, whose density ∝ e^{κc} on [−1, 1]:
//   c = 1 + log(ξ + (1 − ξ) e^{−2κ}) / κ.
Vec3 sampleVmf(const VmfLobe& lobe, Sample2 u) {
    float c;
    if (lobe.kappa < 1e-4f) {
        c = 1.0f - 2.0f * u.u;
    } else {
        const double k = lobe.kappa;
        c = float(1.0 + std::log(u.u + (1.0 - u.u) * std::exp(-2.0 * k)) / k);
        c = std::clamp(c, -1.0f, 1.0f);
    }
    const float s = std::sqrt(std::max(0.0f, 1.0f - c * c));
    const float phi = 2.0f * kPi * u.v;
    return Frame(lobe.mu).toWorld(Vec3(s * std::cos(phi), s * std::sin(phi), c));
}

float vmfMeanCosine(float kappa) {
    const double k = kappa;
    if (k < 1e-3) return float(k / 3.0);
    return float(1.0 / std::tanh(k) - 1.0 / k);
}

float vmfKappaForMeanCosine(float r) {
    r = std::clamp(r, 0.0f, 0.999f);
    if (r < 1e-4f) return 3.0f * r;
    double k = r * (3.0 - double(r) * r) / (1.0 - double(r) * r);
    for (int i = 0; i < 6; ++i) {  // Newton on A(κ) = coth κ − 1/κ, A'(κ) = 1/κ² − 1/sinh²κ
        const double sh = std::sinh(std::min(k, 300.0));
        const double a = 1.0 / std::tanh(k) - 1.0 / k - r;
        const double da = 1.0 / (k * k) - (k < 300.0 ? 1.0 / (sh * sh) : 0.0);
        if (!(da > 0)) break;
        k = std::max(1e-4, k - a / da);
    }
    return float(k);
}

VmfLobe hgAsVmf(Vec3 d, float g) {
    // A scene has few anisotropies: the last one's κ is kept (Newton's method costs more
    // than the rest of a guided vertex).
    thread_local float lastG = 0.0f, lastKappa = 0.0f;
    if (g != lastG) {
        lastKappa = vmfKappaForMeanCosine(std::abs(g));
        lastG = g;
    }
    VmfLobe l;
    l.mu = g >= 0 ? d : -d;
    l.kappa = lastKappa;
    return l;
}

// Beyond κ = 10, 1 − e^{−2κ} is 1 to float precision.
float vmfScale(float kappa) {
    if (kappa < 1e-4f) return kInv4Pi;
    const float tail = kappa < 0.05f ? -std::expm1(-2.0f * kappa) : (kappa < 10.0f ? 1.0f - std::exp(-2.0f * kappa) : 1.0f);
    return kappa / (2.0f * kPi * tail);
}

void VmfMixture::prepare() {
    for (int i = 0; i < count; ++i) scale[i] = vmfScale(lobe[i].kappa);
    prepared = true;
}

float VmfMixture::pdf(Vec3 w) const {
    float p = 0;
    if (!prepared) {
        for (int i = 0; i < count; ++i) p += weight[i] * vmfPdf(lobe[i], w);
        return p;
    }
    for (int i = 0; i < count; ++i)
        p += weight[i] * scale[i] * std::exp(lobe[i].kappa * (std::min(dot(lobe[i].mu, w), 1.0f) - 1.0f));
    return p;
}

Vec3 VmfMixture::sample(Sample2 u) const {
    int i = 0;
    float x = u.u;
    for (; i + 1 < count; ++i) {
        if (x < weight[i]) break;
        x -= weight[i];
    }
    const float wi = weight[i];
    u.u = wi > 0 ? std::min(x / wi, 0x1.fffffep-1f) : 0.5f;
    return sampleVmf(lobe[i], u);
}

// The product's weights, with S(κ) = vmfScale(κ) = C(κ)e^κ:
//   w'_i ∝ w_i C(κ_i) C(κ_l) / C(κ'_i) = w_i S(κ_i) S(κ_l) / S(κ'_i) · e^{κ'_i − κ_i − κ_l};
// S(κ_l) is common to all and drops out, and κ'_i − κ_i − κ_l ≤ 0 (|a + b| ≤ |a| + |b|);
// the largest exponent is taken out before exp so that not all of them underflow.
bool vmfProduct(const VmfMixture& m, const VmfLobe& l, VmfMixture* out) {
    if (l.kappa < 1e-4f) {  // a uniform factor: the mixture itself
        *out = m;
        if (!out->prepared) out->prepare();
        float total = 0;
        for (int i = 0; i < m.count; ++i) total += m.weight[i];
        return total > 0;
    }
    out->count = m.count;
    float factor[VmfMixture::kMaxLobes], exponent[VmfMixture::kMaxLobes];
    float top = -1e30f;
    for (int i = 0; i < m.count; ++i) {
        const Vec3 v = m.lobe[i].mu * m.lobe[i].kappa + l.mu * l.kappa;
        const float k = length(v);
        out->lobe[i].kappa = k;
        out->lobe[i].mu = k > 0 ? v / k : Vec3(0.0f, 0.0f, 1.0f);
        out->scale[i] = vmfScale(k);
        const float si = m.prepared ? m.scale[i] : vmfScale(m.lobe[i].kappa);
        factor[i] = m.weight[i] * si / out->scale[i];
        exponent[i] = k - m.lobe[i].kappa - l.kappa;
        if (factor[i] > 0) top = std::max(top, exponent[i]);
    }
    out->prepared = true;
    float sum = 0;
    for (int i = 0; i < m.count; ++i) sum += out->weight[i] = factor[i] > 0 ? factor[i] * std::exp(exponent[i] - top) : 0.0f;
    if (!(sum > 0) || !std::isfinite(sum)) return false;
    for (int i = 0; i < m.count; ++i) out->weight[i] /= sum;
    return true;
}

}  // namespace brume
