#include "brume/scene/light_selection.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "brume/math/fast_atan.h"
#include "brume/scene/light.h"

namespace brume {

namespace {

// The floor of power's pmf in every pick (light_selection.h).
constexpr double kPowerShare = 0.1;

float grey(const Spectrum& s) { return (s.x + s.y + s.z) / 3.0f; }

// atan(x) for any x, without branches (fast_atan.h's polynomial; ±π/2 for ±∞).
inline float atanAny(float x) {
    constexpr float kHalfPi = 1.57079632679f;
    const float ax = std::fabs(x);
    const float a0 = atanUnit(std::min(ax, 1.0f / ax));  // (1/0 = ∞: both computed, no branch)
    const float a = ax > 1.0f ? kHalfPi - a0 : a0;
    return std::copysign(a, x);
}

}  // namespace

struct LightSelection::Table {
    uint64_t owner = 0;  // LightSelection::id_ (0: empty)
    float key[7] = {};
    double cdf[kMaxLights] = {};  // cdf[i] = P(pick ≤ i)
};

LightSelection::LightSelection(const std::vector<Light>& lights, const Distribution1D& power) : power_(&power) {
    static std::atomic<uint64_t> next{1};
    id_ = next++;
    if (lights.size() < 2 || lights.size() > size_t(kMaxLights) || power.empty()) return;
    for (const Light& l : lights)
        if (l.atInfinity()) return;
    for (size_t i = 0; i < lights.size(); ++i) {
        const Light& l = lights[i];
        const bool planar = l.isPlanar();
        const Vec3 p = planar ? l.emitterCentre : l.position;
        const Vec3 n = planar ? l.shape.n : l.direction;
        src_.px.push_back(p.x), src_.py.push_back(p.y), src_.pz.push_back(p.z);
        src_.nx.push_back(n.x), src_.ny.push_back(n.y), src_.nz.push_back(n.z);
        src_.intensity.push_back(planar ? l.power / kPi / (l.doubleSided ? 2.0f : 1.0f) : grey(l.intensity));
        src_.minD2.push_back(std::max(planar ? l.emitterArea : l.radius * l.radius, 1e-8f));
        src_.planar.push_back(planar ? 1.0f : 0.0f);
        src_.twoSided.push_back(planar && l.doubleSided ? 1.0f : 0.0f);
        // The spot factor's parameters (weightsAt): glTF's scale and offset, or Cycles' cone.
        const bool spot = l.kind == LightKind::Spot;
        const float spotScale = 1.0f / std::max(0.001f, l.cosInner - l.cosOuter);
        src_.spotScale.push_back(spot && !l.cyclesSpot ? spotScale : 0.0f);
        src_.spotOffset.push_back(spot && !l.cyclesSpot ? -l.cosOuter * spotScale : 1.0f);
        src_.cycles.push_back(spot && l.cyclesSpot ? 1.0f : 0.0f);
        src_.cosOuter.push_back(l.cosOuter);
        src_.invSmooth.push_back(l.spotSmooth > 0 ? 1.0f / l.spotSmooth : 1e30f);
        src_.power.push_back(power.pmf(int(i)));
    }
    count_ = int(lights.size());
    spatial_ = true;
    for (int i = 0; i < count_; ++i) {
        if (src_.planar[size_t(i)] > 0) continue;
        along_.px.push_back(src_.px[size_t(i)]), along_.py.push_back(src_.py[size_t(i)]), along_.pz.push_back(src_.pz[size_t(i)]);
        along_.intensity.push_back(src_.intensity[size_t(i)]);
        along_.minD2.push_back(src_.minD2[size_t(i)]);
        along_.index.push_back(i);
    }
    // Along segments only point-like lights are steered, among themselves: with fewer than two
    // there is nothing to steer, and the segment's sums would be spent for power's pick.
    steerAlong_ = std::count(src_.planar.begin(), src_.planar.end(), 0.0f) >= 2;
}

// From x: I·spot/max(r², minD2), or L·A·cos⁺/max(r², A). Branch-free as the segment's loop
// below: every light's cos c is computed; the spot factor is glTF's clamp(c·scale + offset,
// 0, 1)² (scale 0, offset 1 for lights without a cone) or Cycles' c·smoothstep (spotAttenuation,
// light.h); the planar factor max(c, −c·twoSided), 1 for lights that are not planar.
void LightSelection::weightsAt(Vec3 x, float* __restrict w) const {
    const float* __restrict px = src_.px.data();
    const float* __restrict py = src_.py.data();
    const float* __restrict pz = src_.pz.data();
    const float* __restrict nx = src_.nx.data();
    const float* __restrict ny = src_.ny.data();
    const float* __restrict nz = src_.nz.data();
    const float* __restrict inten = src_.intensity.data();
    const float* __restrict minD2 = src_.minD2.data();
    const float* __restrict planar = src_.planar.data();
    const float* __restrict twoSided = src_.twoSided.data();
    const float* __restrict scale = src_.spotScale.data();
    const float* __restrict offset = src_.spotOffset.data();
    const float* __restrict cycles = src_.cycles.data();
    const float* __restrict cosOuter = src_.cosOuter.data();
    const float* __restrict invSmooth = src_.invSmooth.data();
    const float x0 = x.x, x1 = x.y, x2 = x.z;
    const int n = count_;
    for (int i = 0; i < n; ++i) {
        const float vx = x0 - px[i], vy = x1 - py[i], vz = x2 - pz[i];
        const float d2 = vx * vx + vy * vy + vz * vz;
        const float c = (nx[i] * vx + ny[i] * vy + nz[i] * vz) / std::sqrt(std::max(d2, 1e-30f));
        const float g = std::min(std::max(c * scale[i] + offset[i], 0.0f), 1.0f);
        const float sm = std::min(std::max((c - cosOuter[i]) * invSmooth[i], 0.0f), 1.0f);
        const float spot = g * g + cycles[i] * (c * sm * sm * (3.0f - 2.0f * sm) - g * g);
        const float facing = std::max(c, -c * twoSided[i]);
        w[i] = inten[i] / std::max(d2, minD2[i]) * spot * (1.0f + planar[i] * (facing - 1.0f));
    }
}

// Along o + t·d, t ∈ [0, tEnd], for point-like lights (planar emitters: 0, fill keeps their
// power's pick): p's foot on the line at t = Δ, at distance D (at least √minD2);
// ∫ dt/(D² + (t − Δ)²) over [0, tEnd] = (atan a − atan b)/D, a = (tEnd − Δ)/D, b = −Δ/D. A
// spot without its cone.
void LightSelection::weightsAlong(Vec3 o, Vec3 d, float tEnd, float* __restrict w) const {
    // Branch-free, so that the loop runs in vector lanes: an unbounded segment's a = +∞ comes
    // out of t1 = 1e30 (atan of a huge or infinite argument is π/2).
    // It runs over the point-like lights only (along_), then scatters their weights.
    const float t1 = std::isfinite(tEnd) ? tEnd : 1e30f;
    const float* __restrict px = along_.px.data();
    const float* __restrict py = along_.py.data();
    const float* __restrict pz = along_.pz.data();
    const float* __restrict inten = along_.intensity.data();
    const float* __restrict minD2 = along_.minD2.data();
    const int n = int(along_.index.size());
    float wc[kMaxLights];
    for (int j = 0; j < n; ++j) {
        const float ex = px[j] - o.x, ey = py[j] - o.y, ez = pz[j] - o.z;
        const float delta = ex * d.x + ey * d.y + ez * d.z;
        const float h2 = std::max(ex * ex + ey * ey + ez * ez - delta * delta, minD2[j]);
        const float invD = 1.0f / std::sqrt(h2);
        const float angle = atanAny((t1 - delta) * invD) - atanAny(-delta * invD);
        wc[j] = inten[j] * std::max(angle, 0.0f) * invD;
    }
    std::fill(w, w + count_, 0.0f);
    for (int j = 0; j < n; ++j) w[along_.index[size_t(j)]] = wc[j];
}

std::vector<float> LightSelection::weightsAt(Vec3 x) const {
    std::vector<float> w(static_cast<size_t>(count_));
    if (count_ > 0) weightsAt(x, w.data());
    return w;
}

std::vector<float> LightSelection::weightsAlong(Vec3 o, Vec3 d, float tEnd) const {
    std::vector<float> w(static_cast<size_t>(count_));
    if (count_ > 0) weightsAlong(o, d, tEnd, w.data());
    return w;
}

// cdf from the weights w of the lights steered (all, or the point-like ones): a steered light
// i gets P(i) = P_s·(kPowerShare·power(i)/P_s + (1 − kPowerShare)·w_i/Σw), P_s = the steered
// lights' power share, so the others keep their power's pick; power alone where every weight
// is 0 (or the sum overflows).
void LightSelection::fill(Table& t, const float* w, bool pointLikeOnly) const {
    double sum = 0, steered = 0;
    for (int i = 0; i < count_; ++i) {
        if (pointLikeOnly && src_.planar[size_t(i)] > 0) continue;
        sum += double(w[i]);
        steered += src_.power[size_t(i)];
    }
    const bool steer = sum > 0 && std::isfinite(sum);
    double acc = 0;
    for (int i = 0; i < count_; ++i) {
        const double p = src_.power[size_t(i)];
        const bool mine = !(pointLikeOnly && src_.planar[size_t(i)] > 0);
        acc += steer && mine ? kPowerShare * p + (1.0 - kPowerShare) * steered * double(w[i]) / sum : p;
        t.cdf[i] = acc;
    }
}

// The sums of the last point and the last segment, per thread (light_selection.h).
const LightSelection::Table& LightSelection::tableAt(Vec3 x) const {
    thread_local Table t;
    if (t.owner == id_ && t.key[0] == x.x && t.key[1] == x.y && t.key[2] == x.z) return t;
    float w[kMaxLights];
    weightsAt(x, w);
    fill(t, w, false);
    t.owner = id_;
    t.key[0] = x.x, t.key[1] = x.y, t.key[2] = x.z;
    return t;
}

const LightSelection::Table& LightSelection::tableAlong(Vec3 o, Vec3 d, float tEnd) const {
    thread_local Table t;
    const float key[7] = {o.x, o.y, o.z, d.x, d.y, d.z, tEnd};
    if (t.owner == id_ && std::equal(key, key + 7, t.key)) return t;
    float w[kMaxLights];
    weightsAlong(o, d, tEnd, w);
    fill(t, w, true);
    t.owner = id_;
    std::copy(key, key + 7, t.key);
    return t;
}

// The first light whose cdf exceeds u·total (the total is 1 up to rounding), skipping lights
// of probability 0.
int LightSelection::sample(const Table& t, float u, float* p) const {
    const double target = double(u) * t.cdf[count_ - 1];
    int i = int(std::upper_bound(t.cdf, t.cdf + count_, target) - t.cdf);
    i = std::min(i, count_ - 1);
    while (i > 0 && !(t.cdf[i] > t.cdf[i - 1])) --i;
    *p = pmf(t, i);
    return i;
}

float LightSelection::pmf(const Table& t, int i) const {
    return float((t.cdf[i] - (i > 0 ? t.cdf[i - 1] : 0.0)) / t.cdf[count_ - 1]);
}

int LightSelection::sampleAt(Vec3 x, float u, float* p) const {
    if (!spatial_) return power_->sample(u, p);
    return sample(tableAt(x), u, p);
}

float LightSelection::pmfAt(Vec3 x, int light) const {
    if (!spatial_) return power_->pmf(light);
    return pmf(tableAt(x), light);
}

int LightSelection::sampleAlong(Vec3 o, Vec3 d, float tEnd, float u, float* p) const {
    if (!steerAlong_) return power_->sample(u, p);
    return sample(tableAlong(o, d, tEnd), u, p);
}

float LightSelection::pmfAlong(Vec3 o, Vec3 d, float tEnd, int light) const {
    if (!steerAlong_) return power_->pmf(light);
    return pmf(tableAlong(o, d, tEnd), light);
}

}  // namespace brume
