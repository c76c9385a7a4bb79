// Surface BSDFs: sampled directions follow Bsdf::pdf (chi-square), sample weights equal
// eval/pdf, the Lambertian albedo is conserved, and the smooth dielectric obeys Snell's law
// and Fresnel's split.
#include <catch2/catch.hpp>

#include <cmath>

#include "brume/scene/bsdf.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {

Material glossy(float metallic, float roughness) {
    Material m;
    m.kind = MaterialKind::Glossy;
    m.metallic = metallic;
    m.roughness = roughness;
    return m;
}

// A shading normal tilted off the geometric one, as interpolated normals are.
const Vec3 kNg = normalize(Vec3(0.1f, 0.2f, 1.0f));
const Vec3 kNs = normalize(Vec3(0.15f, 0.1f, 1.0f));

}  // namespace

TEST_CASE("BSDF sampling matches Bsdf::pdf (chi-square, p > 0.01 / cases)", "[chi2][bsdf]") {
    struct Case {
        const char* name;
        Material m;
        Vec3 wo;
    };
    Material diffuse;
    const Case cases[] = {
        {"diffuse, wo oblique", diffuse, normalize(Vec3(0.6f, 0.1f, 0.5f))},
        {"diffuse, wo from below (two-sided reflection)", diffuse, normalize(Vec3(0.3f, 0.1f, -0.8f))},
        {"glossy m=0.5 r=0.4", glossy(0.5f, 0.4f), normalize(Vec3(-0.4f, 0.2f, 0.7f))},
        {"metal m=1 r=0.2, grazing", glossy(1.0f, 0.2f), normalize(Vec3(0.9f, 0.0f, 0.2f))},
        {"metal m=1 r=0.7", glossy(1.0f, 0.7f), normalize(Vec3(0.2f, -0.3f, 0.9f))},
    };
    const double alpha = 0.01 / double(std::size(cases));
    for (const Case& c : cases) {
        Bsdf bsdf(c.m, Spectrum(0.7f, 0.5f, 0.3f), kNg, kNs);
        Pcg32 lobeRng(99, 1);
        auto sampleFn = [&](Sample2 u) -> std::optional<Vec3> {
            BsdfSample s;
            float uLobe = float(lobeRng.next() >> 8) * 0x1p-24f;
            if (!bsdf.sample(c.wo, uLobe, u, &s)) return std::nullopt;
            return s.wi;
        };
        auto pdfFn = [&](Vec3 wi) { return double(bsdf.pdf(c.wo, wi)); };
        SphereHistogramOptions opt;
        opt.seed = 5;
        opt.axis = kNg;
        // The densities' mass below the surface (GGX reflections that go under it) is where
        // sampling fails: that probability is 1 − ∫pdf, found by a first quadrature-only call.
        double integral = sphereHistogramTest(sampleFn, pdfFn, 20, 40, 1, opt).pdfIntegral;
        opt.outsideProbability = std::max(0.0, 1.0 - integral);
        HistogramResult r = sphereHistogramTest(sampleFn, pdfFn, 20, 40, 1000000, opt);
        INFO(c.name << ": ∫pdf = " << r.pdfIntegral << "\n" << r.chi2.table);
        CHECK(r.invalid == 0);
        CHECK(r.chi2.pValue > alpha);
        CHECK(r.pdfIntegral <= 1.0 + 1e-3);
        CHECK(r.pdfIntegral > 0.5);
    }
}

TEST_CASE("BSDF sample weights equal eval/pdf and Lambert conserves its albedo", "[bsdf]") {
    Material diffuse;
    for (const Material& m : {diffuse, glossy(0.5f, 0.4f), glossy(1.0f, 0.1f)}) {
        Bsdf bsdf(m, Spectrum(0.7f, 0.5f, 0.3f), kNg, kNs);
        Vec3 wo = normalize(Vec3(0.3f, -0.2f, 0.8f));
        Sampler sampler(3, 4, 5);
        for (int i = 0; i < 1000; ++i) {
            BsdfSample s;
            float uLobe = sampler.next1D();
            if (!bsdf.sample(wo, uLobe, sampler.next2D(), &s)) continue;
            Spectrum expected = bsdf.eval(wo, s.wi) / bsdf.pdf(wo, s.wi);
            for (int c = 0; c < 3; ++c) CHECK(s.weight[c] == Approx(expected[c]).epsilon(1e-3));
            CHECK(s.pdf == Approx(bsdf.pdf(wo, s.wi)).epsilon(1e-4));
        }
    }
    // White Lambert: E[weight] = albedo = 1 exactly (the weight is 1 for every sample).
    Material white;
    white.baseColor = Spectrum(1.0f);
    Bsdf lambert(white, Spectrum(1.0f), Vec3(0, 0, 1), Vec3(0, 0, 1));
    Sampler sampler(8, 8, 8);
    RunningStats stats;
    for (int i = 0; i < 100000; ++i) {
        BsdfSample s;
        float uLobe = sampler.next1D();
        stats.add(lambert.sample(Vec3(0, 0, 1), uLobe, sampler.next2D(), &s) ? s.weight.x : 0.0);
    }
    CHECK(stats.mean() == Approx(1.0).epsilon(1e-3));
}

TEST_CASE("smooth dielectric: Snell's law, Fresnel split, radiance scaling", "[bsdf]") {
    Material glass;
    glass.kind = MaterialKind::Dielectric;
    glass.ior = 1.5f;
    Vec3 n(0, 0, 1);
    Bsdf bsdf(glass, Spectrum(1.0f), n, n);
    CHECK(bsdf.isSpecular());
    for (float side : {1.0f, -1.0f}) {  // outside (front) and inside
        Vec3 wo = normalize(Vec3(0.3f, 0.0f, 0.8f * side));
        float cosI = std::abs(wo.z), eta = side > 0 ? 1.5f : 1.0f / 1.5f;
        float F = fresnelDielectric(cosI, eta);
        // Just below F reflects, just above refracts.
        BsdfSample r, t;
        REQUIRE(bsdf.sample(wo, F * 0.999f, Sample2{0.5f, 0.5f}, &r));
        CHECK_FALSE(r.transmitted);
        CHECK(r.pdf == Approx(F));
        CHECK(r.wi.z == Approx(wo.z));
        CHECK(r.wi.x == Approx(-wo.x));
        REQUIRE(bsdf.sample(wo, std::min(0.9999f, F + 1e-3f), Sample2{0.5f, 0.5f}, &t));
        CHECK(t.transmitted);
        CHECK(t.pdf == Approx(1.0f - F));
        CHECK(t.wi.z * wo.z < 0);
        // Snell: sinθi = η sinθt with η = ηt/ηi.
        float sinI = std::sqrt(1 - wo.z * wo.z), sinT = std::sqrt(1 - t.wi.z * t.wi.z);
        CHECK(sinI == Approx(eta * sinT).epsilon(1e-4));
        CHECK(t.weight.x == Approx(1.0f / (eta * eta)).epsilon(1e-5));
    }
    // Total internal reflection from inside beyond the critical angle.
    Vec3 grazing = normalize(Vec3(0.9f, 0.0f, -0.2f));
    BsdfSample s;
    REQUIRE(bsdf.sample(grazing, 0.99f, Sample2{0.5f, 0.5f}, &s));
    CHECK_FALSE(s.transmitted);
    CHECK(fresnelDielectric(0.2f, 1.0f / 1.5f) == 1.0f);
    // Normal incidence: F = ((η−1)/(η+1))² = 0.04.
    CHECK(fresnelDielectric(1.0f, 1.5f) == Approx(0.04f).epsilon(1e-4));
}
