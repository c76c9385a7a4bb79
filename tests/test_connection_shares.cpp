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
