// --stats' technique sums (technique_sums.h): every weighted contribution is counted under one
// technique, so over a render the techniques' sums add up to the image (Σ over pixels of the
// mean of the channels, times the passes), for the path tracer and the bidirectional tracer
// (its splats included); and, a sanity bound, each camera-side technique's squares are at least
// its sum squared over the samples (Cauchy–Schwarz: one term per sample).
#include <catch2/catch.hpp>

#include <cmath>

#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"
#include "brume/render/renderer.h"
#include "support/pixel_estimates.h"

using namespace brume;
using namespace brume::test;

namespace {

void checkSums(const Scene& scene, Integrator& integrator, const char* what) {
    const int W = 16, H = 12, spp = 8;
    Film film(W, H);
    RenderOptions o;
    o.width = W;
    o.height = H;
    o.spp = spp;
    o.threads = 2;
    const RenderStats st = render(scene, integrator, o, film);
    double image = 0;
    for (float v : film.rgb()) image += double(v);
    image *= double(spp) / 3.0;
    double sum = 0;
    int used = 0;
    for (int k = 0; k < TechniqueSums::kSlots; ++k) {
        sum += st.techniques.sum[k];
        if (st.techniques.sum[k] != 0) ++used;
        // (A sample's light tracing splats into several pixels, each a term of its own: more
        // terms than samples, so the bound is for the other techniques.)
        const bool splats = k == techniqueSlot(StrategyKind::CameraConnection, false) ||
                            k == techniqueSlot(StrategyKind::CameraConnection, true);
        if (!splats) CHECK(st.techniques.squares[k] * double(st.samples) >= st.techniques.sum[k] * st.techniques.sum[k] * (1 - 1e-9));
    }
    INFO(what << ": techniques sum to " << sum << ", the image to " << image << " (" << used << " techniques)");
    CHECK(used >= 2);
    CHECK(std::abs(sum - image) <= 1e-4 * image);
}

}  // namespace

TEST_CASE("technique sums add up to the image", "[stats]") {
    auto scene = loadTestScene("quad_light_fog.gltf");
    PathTracer pt(PathTracerOptions{-1, true, ConnectMode::Mis});
    checkSums(*scene, pt, "pt");
    BdptOptions b{-1, MisHeuristic::Power};
    b.connect = ConnectMode::Mis;
    BdptIntegrator bdpt(b);
    checkSums(*scene, bdpt, "bdpt");
}
