// The efficiency-aware tracer's estimate of each candidate's variance (allocation_statistics.h)
// against the variance the candidate has when it renders: on a point light in fog (full
// transport), the pilot's estimate for a few candidates, relative to its own variance, against
// the measured ratio, from 64 independent one-pass renders of each candidate weighted by the
// first pilot's pixel weights. The estimate of one pilot (1 pass over a quarter of 48×48
// pixels in full transport) is heavy tailed (one seed in five rated p=0 ea=LC 6.9× too
// noisy), so the test holds the median over five pilot seeds of estimate / measured to
// 1 ± 0.25. Measured at seeds 0–4: medians 0.96 (p=0 ea=LC), 0.90 (p=0 ea-only=LC), 1.05
// (p=0.25 ea-only=LC), 1.01 (p=0.25 ea=C), 1.10 (pt+ea); beside the quad light 0.98
// (p=0.25 ea=C), 1.04 (p=0 ea-only=LC), 1.21 (pt+ea) (this build; an earlier one read 0.86,
// 0.94, 0.97, 1.00, 1.11 and 0.99, 0.98, 1.23). (With the max of the moments' groups'
// mean and median everywhere, allocation_planner.cpp groupDifference, they rose where the
// groups disagree: 0.86, 0.98, 1.10, 1.05, 1.11; 1.02, 1.24, 1.23. Now the median is taken
// only where the mean reads a variance below zero.) Without each candidate's own share of a
// pixel's squared mean (ownParts), p=0.25 ea=C, which leaves more of the pixel to light
// tracing, reads 0.70 on the point light and pt+ea, which leaves it none, 1.48 beside the quad
// light: both fail. (The estimate before it, balance-heuristic moments through the pilot's
// weights, read 0.72 and 1.27 on the point light.) Without
// the products of a sample's contributions (C) the ea-only candidates were 1.6–1.9× too noisy
// and the test fails.
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

BdptOptions options(const BdptAllocation* forced, bool partialPilot = false) {
    BdptOptions o{-1, MisHeuristic::Power};
    o.connect = ConnectMode::Mis;
    if (forced) o.allocation = *forced;
    else o.efficiencyAware = true;
    o.partialPilot = partialPilot;
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

// The median over kPilots pilot seeds of estimate / measured, per candidate named; with
// partialPilot, of pilots whose passes render the camera side at the recording pixels alone
// (AllocationPlanner::partialAt: the weights and V_pilot from those pixels).
std::vector<double> medianRatios(const char* sceneFile, const std::vector<std::string>& names, bool partialPilot = false) {
    auto scene = loadTestScene(sceneFile);
    const size_t kNames = names.size();
    std::vector<std::vector<double>> ratios(kNames);  // estimate / measured, per pilot seed
    std::vector<float> weights;
    std::vector<BdptAllocation> candidates(kNames);
    std::vector<double> measured(kNames, 0.0);
    for (int seed = 0; seed < kPilots; ++seed) {
        BdptIntegrator integrator(options(nullptr, partialPilot));
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
            for (size_t k = 0; k < kNames; ++k) {
                REQUIRE(allocationNamed(names[k], ConnectMode::Mis, &candidates[k]));
                measured[k] = measuredVariance(*scene, candidates[k], w) / pilotMeasured;
            }
        }
        for (size_t k = 0; k < kNames; ++k) ratios[k].push_back(estimate(candidates[k]) / pilotEstimate / measured[k]);
    }
    std::vector<double> medians;
    for (size_t k = 0; k < kNames; ++k) {
        std::vector<double> r = ratios[k];
        std::sort(r.begin(), r.end());
        std::string all;
        for (double v : ratios[k]) all += " " + std::to_string(v);
        UNSCOPED_INFO(sceneFile << (partialPilot ? " (partial pilot)" : "") << ", " << names[k]
                                << ": estimate / measured over the pilot seeds:" << all);
        medians.push_back(r[r.size() / 2]);
    }
    return medians;
}

}  // namespace

TEST_CASE("auto's variance estimates follow the candidates' measured variance", "[auto][allocation][heavy]") {
    const std::vector<std::string> names = {"bdpt lt p=0 ea=LC", "bdpt lt p=0 ea-only=LC", "bdpt lt p=0.25 ea-only=LC",
                                            "bdpt lt p=0.25 ea=C", "pt+ea"};
    for (double m : medianRatios("single_near.gltf", names)) CHECK(std::abs(m - 1) < kTolerance);
}

TEST_CASE("auto's variance estimates beside an area light, where light tracing carries much of the image",
          "[auto][allocation][heavy]") {
    const std::vector<std::string> names = {"bdpt lt p=0.25 ea=C", "bdpt lt p=0 ea-only=LC", "pt+ea"};
    for (double m : medianRatios("quad_light_fog.gltf", names)) CHECK(std::abs(m - 1) < kTolerance);
}

// The partial pilot (V_pilot and the weights from the recording pixels alone): at seeds 0–4
// medians 1.02, 0.94, 1.03, 1.14, 1.02 on the point light. Beside the quad light it reads
// 0.97, 0.99 and 1.29 for pt+ea (the whole pilot 1.21: one seed's estimate moved 6 %, with
// V_pilot from a quarter of the pixels), over the bound: not held there (docs/results.md).
TEST_CASE("auto's variance estimates with the partial pilot passes", "[auto][allocation][heavy]") {
    const std::vector<std::string> names = {"bdpt lt p=0 ea=LC", "bdpt lt p=0 ea-only=LC", "bdpt lt p=0.25 ea-only=LC",
                                            "bdpt lt p=0.25 ea=C", "pt+ea"};
    for (double m : medianRatios("single_near.gltf", names, true)) CHECK(std::abs(m - 1) < kTolerance);
}
