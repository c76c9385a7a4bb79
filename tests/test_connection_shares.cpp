// How often the path tracer makes its light connections in media (connection_shares.h): what
// the learning chooses where a share of 0 cannot leave its technique out. (That every share,
// 0 included, keeps the image unbiased is test_pt_oracles.cpp's.)
#include <catch2/catch.hpp>

#include "brume/film/film.h"
#include "brume/integrators/connection_shares.h"
#include "brume/integrators/path_tracer.h"
#include "brume/render/renderer.h"
#include "support/pixel_estimates.h"

using namespace brume;
using namespace brume::test;

namespace {

const ConnectionShares& learned(const Scene& scene, PathTracer& pt) {
    Film film(16, 16);
    RenderOptions r;
    r.width = 16;
    r.height = 16;
    r.spp = ConnectionShares::kLearningPasses;
    render(scene, pt, r, film);
    REQUIRE(pt.connectionShares());
    REQUIRE_FALSE(pt.connectionShares()->learning());
    return *pt.connectionShares();
}

}  // namespace

// In single scattering the walk passes through the medium at its one event, so C alone makes
// the light's paths there and a share of 0 on segments is read as 1 (madeWith): it leaves
// nothing out and saves no call. Before its cost counted those calls it looked a third
// cheaper at the same variance, and the learning chose it ("on segments 0.00" in --stats,
// while every C was made).
TEST_CASE("connection shares: a share of 0 is not rated cheaper where it saves nothing", "[pt]") {
    auto scene = loadTestScene("single_near.gltf");
    PathTracerOptions o{1, true, ConnectMode::Mis};
    o.learnShares = true;
    PathTracer pt(o);
    const ConnectionShares& shares = learned(*scene, pt);
    INFO(shares.report());
    CHECK(shares.shares().segment == 1.0f);
}

// A render stopped inside the learning passes keeps their sums (the candidates' moments, the
// calls at vertices and where the walk passes through) in its state: loaded into a fresh
// learner they come back byte for byte; a truncated state is refused.
TEST_CASE("connection shares: the learning state survives a save and load", "[pt]") {
    auto scene = loadTestScene("single_near.gltf");
    PathTracerOptions o{1, true, ConnectMode::Mis};
    o.learnShares = true;
    PathTracer pt(o);
    Film film(16, 16);
    RenderOptions r;
    r.width = 16;
    r.height = 16;
    r.spp = ConnectionShares::kLearningPasses - 1;
    render(*scene, pt, r, film);
    REQUIRE(pt.connectionShares());
    const ConnectionShares& a = *pt.connectionShares();
    REQUIRE(a.learning());
    ConnectionShares copy;
    copy.loadState(a.saveState());
    CHECK(copy.learning());
    CHECK(copy.saveState() == a.saveState());
    CHECK_THROWS(copy.loadState(a.saveState().substr(0, a.saveState().size() - 3)));
}

namespace {

// Eight learning passes of a 1×1 image whose one sample has two light-connection records, A
// (at a medium vertex) and C (on a segment), each a path the other could make (equal
// densities: weights ½ and ½), with the values given per pass; each pass counts one call of
// each. Returns the shares learned.
ConnectionShares::Shares learnFrom(const double (&a)[8], const double (&c)[8], bool keepSegments = false) {
    ConnectionShares shares;
    shares.keepSegments(keepSegments);
    const StrategyDensities p{1.0, 0.0, 1.0, 0.0};
    for (int pass = 0; pass < ConnectionShares::kLearningPasses; ++pass) {
        const ConnectionShares::Record records[2] = {{ConnectionShares::Technique::Vertex, a[pass], p},
                                                     {ConnectionShares::Technique::Segment, c[pass], p}};
        const double L = 0.5 * a[pass] + 0.5 * c[pass];
        shares.addSample(1, 1, 0, L, records, 2, 1);
        const Spectrum radiance{float(L), float(L), float(L)};
        PassSummary summary;
        summary.pass = pass;
        summary.complete = true;
        summary.width = summary.height = 1;
        summary.radiance = &radiance;
        PathTracerCounts& n = summary.totals.counts.pt;
        n.samples = n.walkRays = n.vertexCalls = n.vertexRays = n.segmentCalls = n.segmentTracingCalls = 1;
        shares.endPass(summary);
    }
    REQUIRE_FALSE(shares.learning());
    UNSCOPED_INFO(shares.report());
    return shares.shares();
}

}  // namespace

// The learning measures each candidate with the numbers the render uses (connection_shares.h):
// the spread between aligned batches of its replayed passes, not the second moment of single
// samples. Both records take the values 0 and 2, four times each, so every candidate has the
// same second moment; but one technique's values are stratified (each aligned pair of passes
// sums to about 2, as Owen-scrambled Sobol numbers give a smooth integrand) and the other's
// are not. The learning keeps the stratified one alone, also where leaving out the other
// costs more (leaving out C saves 1.8 a call, A 1.4): an estimate blind to the batches would
// choose by cost and leave out C in both cases.
TEST_CASE("connection shares: the learning sees each technique's stratification", "[pt][quick]") {
    const double stratified[8] = {2.0, 0.0, 0.0, 2.1, 2.0, 0.1, 0.0, 1.9};
    const double white[8] = {2.0, 2.0, 2.0, 0.0, 0.0, 0.0, 0.0, 2.0};
    const ConnectionShares::Shares keepA = learnFrom(stratified, white);
    CHECK(keepA.vertex == 1.0f);
    CHECK(keepA.segment == 0.0f);
    const ConnectionShares::Shares keepC = learnFrom(white, stratified);
    CHECK(keepC.vertex == 0.0f);
    CHECK(keepC.segment == 1.0f);
}

namespace {

// The path tracer's learning on a test scene with a point-like light in fog keeps C, and its
// report names why.
void checkKeepsC(const char* sceneName) {
    auto scene = loadTestScene(sceneName);
    PathTracerOptions o{-1, true, ConnectMode::Mis};
    o.learnShares = true;
    PathTracer pt(o);
    const ConnectionShares& shares = learned(*scene, pt);
    INFO(shares.report());
    CHECK(shares.shares().segment == 1.0f);
    CHECK(shares.report().find("not a candidate: a point-like light in a medium") != std::string::npos);
}

}  // namespace

// Where a point or spot light lies inside a medium, leaving C out would leave A alone near
// it, with infinite variance (connection_shares.h, keepSegments): the learning that keeps A
// alone above keeps C too there, and the path tracer rules it out in a scene with a point
// light in fog.
TEST_CASE("connection shares: C is not left out where a point light lies in a medium", "[pt][quick]") {
    const double stratified[8] = {2.0, 0.0, 0.0, 2.1, 2.0, 0.1, 0.0, 1.9};
    const double white[8] = {2.0, 2.0, 2.0, 0.0, 0.0, 0.0, 0.0, 2.0};
    const ConnectionShares::Shares kept = learnFrom(stratified, white, true);
    CHECK(kept.segment == 1.0f);
    checkKeepsC("single_near.gltf");  // a point light inside the fog
}

// The same beside a sphere light in fog: A alone is not unbounded there (a light point's
// solid angle is at most 2π), but from free-flight points near a small sphere it carries
// (R/r)², rare values far above the haze's that 8 learning passes do not show (dusk_haze,
// 0.12-m lamps: A alone learned at 2 seeds of 12, single pixels 20–50× their mean).
TEST_CASE("connection shares: C is not left out where a sphere light lies in a medium", "[pt][quick]") {
    checkKeepsC("sphere_light_fog.gltf");  // a 0.25-m sphere light inside the fog
}
