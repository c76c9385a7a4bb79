// Von Mises–Fisher lobes on the sphere and small mixtures of them: the directional
// distributions path guiding learns (docs/path-guiding.md).
//   vMF(w; μ, κ) = κ / (4π sinh κ) · exp(κ μ·w),   normalised over the sphere;
//   κ = 0 is the uniform density 1/(4π).
// Products of lobes are lobes again: vMF(μ1,κ1)·vMF(μ2,κ2) = s · vMF(μ, κ) with
// κμ = κ1μ1 + κ2μ2 and s = C(κ1)C(κ2)/C(κ), C(κ) the normalisation above; so the product of a
// mixture with one lobe (a phase function fitted as a lobe) is again a mixture whose density
// can be evaluated exactly.
#pragma once
#include "brume/math/vec3.h"
#include "brume/sampling/sampler.h"

namespace brume {

struct VmfLobe {
    Vec3 mu{0.0f, 0.0f, 1.0f};
    float kappa = 0;
};

// log C(κ) = log(κ / (4π sinh κ)), stable for κ → 0 and κ ≫ 1.
double vmfLogNorm(double kappa);
// C(κ)·e^κ = κ / (2π (1 − e^{−2κ})) (1/(4π) at κ = 0): vMF(w) = that · e^{κ(μ·w − 1)}.
float vmfScale(float kappa);
float vmfPdf(const VmfLobe& lobe, Vec3 w);
Vec3 sampleVmf(const VmfLobe& lobe, Sample2 u);
// The mean cosine coth κ − 1/κ of a lobe about its axis, and its inverse (κ for a mean
// cosine r in [0, 1), by Newton's method from Banerjee's approximation r(3 − r²)/(1 − r²)).
float vmfMeanCosine(float kappa);
float vmfKappaForMeanCosine(float r);

// A Henyey–Greenstein lobe of anisotropy g about the propagation direction d, as the vMF
// lobe of the same mean cosine (about −d for g < 0): the phase factor of product sampling.
VmfLobe hgAsVmf(Vec3 d, float g);

struct VmfMixture {
    static constexpr int kMaxLobes = 8;
    int count = 0;
    float weight[kMaxLobes] = {};  // sum to 1 over the first `count`
    VmfLobe lobe[kMaxLobes];
    // vmfScale(κ) of each lobe, once prepare() has run (pdf() then needs one exp a lobe);
    // a change to the lobes afterwards needs prepare() again.
    float scale[kMaxLobes] = {};
    bool prepared = false;

    void prepare();
    float pdf(Vec3 w) const;
    // u.u picks the lobe (and is rescaled to sample within it).
    Vec3 sample(Sample2 u) const;
};

// The mixture times one lobe, renormalised: false if the product vanishes.
bool vmfProduct(const VmfMixture& m, const VmfLobe& lobe, VmfMixture* out);

}  // namespace brume
