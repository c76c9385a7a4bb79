// The efficiency-aware tracer's estimate of each candidate's variance (allocation_statistics.h)
// against the variance the candidate has when it renders: on a point light in fog (full
// transport), the pilot's estimate for a few candidates, relative to its own variance, against
// the measured ratio, from 64 independent one-pass renders of each candidate weighted by the
// first pilot's pixel weights. The estimate of one pilot (1 pass over a quarter of 48×48
// pixels in full transport; 3 before the pilot was shortened, when these medians were
// measured, and the test still passes with 1) is heavy tailed (one seed in five rated p=0 ea=LC 2.1× too noisy), so the test holds
// the median over five pilot seeds of estimate / measured to 1 ± 0.25. Measured at seeds 0–4:
// medians 0.94 (p=0 ea=LC), 1.09 (p=0 ea-only=LC), 1.19 (p=0.25 ea-only=LC); without the
// products of a sample's contributions (C) the ea-only candidates were 1.6–1.9× too noisy at
// seed 0 and the test fails. (pt+ea's estimate spreads 0.9–1.7× over those seeds, median 1.4:
// not held here.)
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "brume/integrators/allocation_planner.h"
#include "brume/integrators/bdpt.h"
#include "brume/integrators/bdpt_allocation.h"
#include "brume/render/renderer.h"
#include "support/pixel_estimates.h"

using namespace brume;
using namespace brume::test;

namespace {

constexpr int kW = 48, kH = 48;
constexpr int kMeasuredPasses = 64;
constexpr int kPilots = 5;
constexpr double kTolerance = 0.25;

BdptOptions options(const BdptAllocation* forced) {
    BdptOptions o{-1, MisHeuristic::Power};
    o.connect = ConnectMode::Mis;
    if (forced) o.allocation = *forced;
    else o.efficiencyAware = true;
    return o;
}

// Σ over pixels and channels of w · the unbiased variance of one independent pass.
double measuredVariance(const Scene& scene, const BdptAllocation& a, const PixelWeights& weights) {
    std::vector<double> sum(size_t(kW) * kH * 3, 0.0), squares(sum.size(), 0.0);
    for (int k = 0; k < kMeasuredPasses; ++k) {
        BdptIntegrator integrator(options(&a));
        Film film(kW, kH);
        RenderOptions o;
        o.width = kW;
        o.height = kH;
        o.spp = 1;
        o.seed = 1000 + uint64_t(k);
        o.sampler = SamplerKind::Independent;
        o.threads = 2;
        render(scene, integrator, o, film);
        const std::vector<float> rgb = film.rgb();
        for (size_t i = 0; i < sum.size(); ++i) {
            sum[i] += rgb[i];
            squares[i] += double(rgb[i]) * rgb[i];
        }
    }
    double v = 0;
    const double n = kMeasuredPasses;
    for (size_t i = 0; i < sum.size(); ++i) v += double(weights.w[i]) * (squares[i] - sum[i] * sum[i] / n) / (n - 1);
    return v;
}

}  // namespace

TEST_CASE("auto's variance estimates follow the candidates' measured variance", "[auto][allocation][heavy]") {
    auto scene = loadTestScene("single_near.gltf");
    const char* names[] = {"bdpt lt p=0 ea=LC", "bdpt lt p=0 ea-only=LC", "bdpt lt p=0.25 ea-only=LC"};
    std::vector<double> ratios[3];  // estimate / measured, per pilot seed
    std::vector<float> weights;
    BdptAllocation candidates[3];
    double measured[3] = {};
    for (int seed = 0; seed < kPilots; ++seed) {
        BdptIntegrator integrator(options(nullptr));
        Film film(kW, kH);
        RenderOptions o;
        o.width = kW;
        o.height = kH;
        o.spp = integrator.planner()->decisionPass() + 1;
        o.seed = uint64_t(seed);
        o.threads = 2;
        render(*scene, integrator, o, film);
        const AllocationPlanner& planner = *integrator.planner();
        REQUIRE(planner.estimates().size() == planner.candidates().size());
        auto estimate = [&](const BdptAllocation& a) {
            for (size_t j = 0; j < planner.candidates().size(); ++j)
                if (planner.candidates()[j] == a) return planner.estimates()[j].variance;
            return 0.0;
        };
        const BdptAllocation pilot = pilotAllocation();
        const double pilotEstimate = estimate(pilot);
        REQUIRE(pilotEstimate > 0);
        // Measured once, with the first pilot's pixel weights (the others' differ by the
        // noise of a smoothed pass).
        if (seed == 0) {
            weights.assign(planner.weights().w, planner.weights().w + size_t(kW) * kH * 3);
            const PixelWeights w{kW, kH, weights.data()};
            const double pilotMeasured = measuredVariance(*scene, pilot, w);
            for (int k = 0; k < 3; ++k) {
                REQUIRE(allocationNamed(names[k], ConnectMode::Mis, &candidates[k]));
                measured[k] = measuredVariance(*scene, candidates[k], w) / pilotMeasured;
            }
        }
        for (int k = 0; k < 3; ++k) ratios[k].push_back(estimate(candidates[k]) / pilotEstimate / measured[k]);
    }
    for (int k = 0; k < 3; ++k) {
        std::vector<double> r = ratios[k];
        std::sort(r.begin(), r.end());
        std::string all;
        for (double v : ratios[k]) all += " " + std::to_string(v);
        INFO(names[k] << ": estimate / measured over the pilot seeds:" << all);
        CHECK(std::abs(r[r.size() / 2] - 1) < kTolerance);
    }
}
