// One stability case: a scene rendered by every method and compared with a reference, one
// row of the table in docs/results.md ("Stability suite") per method.
//
// The reference is either one method at 4× the samples with another seed (the case's most
// robust method: the path tracer unless a case says otherwise and why), or, for a case with a
// twin (an equivalent scene: the same scene at the origin, or without its degenerate
// triangles), each method on the twin with the same samples: then the case asks whether that
// method's answer changes, whatever its weaknesses elsewhere, and also that its cost per
// sample stays within kCostRatio of the twin's.
//
// Checks, per method:
//  - no sample or splat dropped as NaN/Inf by the renderer, every pixel finite;
//  - agreement: max |z| over 4×4-pixel blocks and channels below kZ, and |z| of the image mean
//    below kZ. With 32 batches per side the batch-mean z is close to Student-t with ~60 degrees
//    of freedom: a correct method with tame tails exceeds 5 with probability ~1e-5 per block
//    and channel, ~0.01 over the whole suite (~3000 comparisons, ~1000 independent: the
//    channels of grey scenes are not). Measured with the known bugs patched out, over four seed sets, the
//    methods not listed as weak stayed below 4.2 but for one value of 6.4 (now listed).
//    Seeds are fixed, so a pass is reproducible.
//  - the median of means (stability_compare.h) within kMedianOfMeansBound of the reference's:
//    the rows that are not weak stayed within 0.09 over three seed sets (but in g_backward,
//    whose image mean no method resolves at this budget: 0.31, and the case says so), so the
//    bound is 0.2, and an image 20 % off fails it whatever its tail;
//  - or, for a method the case lists as weak (its estimates are so heavy-tailed that the
//    per-block z means nothing at this budget: it is measured anyway and printed), bounds on
//    its relative RMSE and outlier fraction (the largest value measured over four seed sets,
//    times two, and at least 0.001 for the outliers), its median of means (the largest over
//    three seed sets, times two, where that is above kMedianOfMeansBound), and, where the image
//    mean stayed Gaussian enough (|z| < 4 over those seed sets), |z| of the image mean below kZ.
#pragma once
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "brume/scene/camera_importance.h"
#include "brume/scene/gltf_loader.h"
#include "brume/scene/scene.h"
#include "stability/stability_compare.h"
#include "stability/stability_methods.h"
#include "stability/stability_table.h"

namespace brume::test {

constexpr double kZ = 5.0;
constexpr double kCostRatio = 10.0;
constexpr double kMedianOfMeansBound = 0.2;
constexpr int kWidth = 16, kHeight = 12, kBlock = 4;

struct Weakness {
    Method method;
    double maxRelRmse;   // bound on the relative RMSE
    double maxOutliers;  // bound on the fraction of values above 10 × the reference
    bool checkMeanZ;     // whether |z| of the image mean is still checked
    double maxMedianOfMeans;  // bound on |relMedianOfMeans|
};

struct StabilityCase {
    std::string name, file;
    std::string twinFile;  // non-empty: each method is compared with itself on this scene
    int maxDepth = -1;
    int sppPt = 64, sppBdpt = 8;  // per batch
    int batches = 32;
    double medianOfMeansBound = kMedianOfMeansBound;  // for the methods not listed as weak
    Method reference = kPtMis;
    std::vector<Weakness> weak;

    StabilityCase(std::string caseName, std::string sceneFile) : name(std::move(caseName)), file(std::move(sceneFile)) {}
    StabilityCase& referenceMethod(Method m) { reference = m; return *this; }
    StabilityCase& sameMethodOn(std::string twin) { twinFile = std::move(twin); return *this; }
    StabilityCase& samples(int pt, int bdpt) { sppPt = pt, sppBdpt = bdpt; return *this; }
    StabilityCase& weakMethod(Method m, double maxRelRmse, double maxOutliers, bool checkMeanZ,
                              double maxMedianOfMeans = kMedianOfMeansBound) {
        weak.push_back({m, maxRelRmse, maxOutliers, checkMeanZ, maxMedianOfMeans});
        return *this;
    }
    // A case whose image mean no method resolves at the suite's budget: a looser bound on the
    // median of means, stated where the case is.
    StabilityCase& meanResolvedTo(double bound) { medianOfMeansBound = bound; return *this; }
    int spp(const Method& m) const { return m.bdpt ? sppBdpt : sppPt; }
};

inline std::unique_ptr<Scene> loadStabilityScene(const std::string& file) {
    return std::make_unique<Scene>(loadGltf(std::string(BRUME_STABILITY_DATA) + "/" + file));
}

// Blocks where a point-like light is imaged directly: point and spot lights, and emissive
// triangles under 1e-6 m² (zero-area ones included). Light tracing images them (a finite
// irradiance at the pinhole); a camera ray hits them with probability 0 or nearly so.
inline std::vector<bool> pointLikeLightBlocks(const Scene& scene) {
    const int bw = kWidth / kBlock, bh = kHeight / kBlock;
    std::vector<bool> mask(size_t(bw) * bh, false);
    auto maskPoint = [&](Vec3 p) {
        CameraConnection cc;
        if (!connectToCamera(scene.camera(), p, kWidth, kHeight, &cc)) return;
        for (float dx : {-0.01f, 0.01f})
            for (float dy : {-0.01f, 0.01f}) {
                int x = int(cc.fx + dx) / kBlock, y = int(cc.fy + dy) / kBlock;
                if (x >= 0 && y >= 0 && x < bw && y < bh) mask[size_t(y) * bw + x] = true;
            }
    };
    for (const Light& l : scene.lights()) {
        if (l.kind == LightKind::Point || l.kind == LightKind::Spot) maskPoint(l.position);
        if (l.kind == LightKind::Triangle && l.shape.area < 1e-6f)
            for (Vec3 p : {l.shape.p0, l.shape.p1, l.shape.p2}) maskPoint(p);
    }
    return mask;
}

inline void requireFinite(const std::string& what, const StabilityRun& run) {
    INFO(what << ": samples or splats dropped as NaN/Inf: " << run.nonFinite);
    CHECK(run.nonFinite == 0);
    CHECK(run.filmFinite);
}

inline const Weakness* findWeakness(const StabilityCase& sc, const Method& m) {
    for (const Weakness& w : sc.weak)
        if (w.method.name() == m.name()) return &w;
    return nullptr;
}

// A method costing more than kCostRatio × its cost on the twin per sample (4 spp each) fails
// and is not rendered in full: that could take hours.
inline bool costWithinTwin(const StabilityCase& sc, const Scene& scene, const Scene& twin, const Method& method,
                           Integrator& integrator) {
    double tTwin = renderBatches(twin, integrator, kWidth, kHeight, 4, 1, 99, kBlock).seconds;
    double tCase = renderBatches(scene, integrator, kWidth, kHeight, 4, 1, 99, kBlock).seconds;
    printCost(sc.name, method.name(), tCase / tTwin);
    bool ok = tCase < kCostRatio * tTwin + 0.05;
    INFO(sc.name << " " << method.name() << ": " << tCase << " s for 4 spp, on " << sc.twinFile << " " << tTwin << " s");
    CHECK(ok);
    return ok;
}

inline void checkComparison(const std::string& what, const Comparison& c, const Weakness* weak, double medianOfMeansBound) {
    INFO(what << ": worst " << c.worst << " (max |z| " << c.maxZ << "); image mean z " << c.zMean << ", bias "
              << c.relBias << " (resolution " << c.relSeMean << "), relative RMSE " << c.relRmse << ", outliers "
              << c.outliers);
    CHECK(std::abs(c.relMedianOfMeans) < (weak ? weak->maxMedianOfMeans : medianOfMeansBound));
    if (weak) {
        CHECK(c.relRmse < weak->maxRelRmse);
        CHECK(c.outliers < weak->maxOutliers);
        if (weak->checkMeanZ) CHECK(std::abs(c.zMean) < kZ);
    } else {
        CHECK(c.maxZ < kZ);
        CHECK(std::abs(c.zMean) < kZ);
    }
}

// The seed set: 0 in the tests; BRUME_STABILITY_SEED_BASE=k (k = 100, 200, …) gives others, to
// measure the spread of the numbers the bounds are set from.
inline uint64_t stabilitySeedBase() {
    const char* s = std::getenv("BRUME_STABILITY_SEED_BASE");
    return s ? std::strtoull(s, nullptr, 10) : 0;
}

// seedBase: 0 in the tests; other values give independent seed sets (to measure the spread).
inline void runStabilityCase(const StabilityCase& sc, uint64_t seedBase = 0) {
    seedBase += stabilitySeedBase();
    auto scene = loadStabilityScene(sc.file);
    auto twin = sc.twinFile.empty() ? nullptr : loadStabilityScene(sc.twinFile);
    const std::vector<bool> mask = pointLikeLightBlocks(*scene);

    StabilityRun shared;  // the common reference, when there is no twin
    if (!twin) {
        auto integrator = sc.reference.make(sc.maxDepth);
        shared = renderBatches(*scene, *integrator, kWidth, kHeight, 4 * sc.spp(sc.reference), sc.batches,
                               seedBase + 1, kBlock);
        printRow(sc.name, "ref " + sc.reference.name(), shared, nullptr);
        requireFinite(sc.name + " reference " + sc.reference.name(), shared);
    }
    uint64_t seed = seedBase + 2;
    StabilityRun referenceRun;  // the reference method's own run, checked after the others
    std::vector<std::pair<Method, StabilityRun>> others;
    for (const Method& method : allMethods()) {
        const std::string what = sc.name + " " + method.name();
        const Weakness* weak = findWeakness(sc, method);
        auto integrator = method.make(sc.maxDepth);
        ++seed;
        StabilityRun own;
        if (twin) {
            if (!costWithinTwin(sc, *scene, *twin, method, *integrator)) continue;
            own = renderBatches(*twin, *integrator, kWidth, kHeight, sc.spp(method), sc.batches, seedBase + 1, kBlock);
            requireFinite(what + " on " + sc.twinFile, own);
        }
        StabilityRun run = renderBatches(*scene, *integrator, kWidth, kHeight, sc.spp(method), sc.batches, seed, kBlock);
        requireFinite(what, run);
        if (!twin && method.name() == sc.reference.name()) {
            referenceRun = std::move(run);
            continue;
        }
        Comparison c = compareRuns(run, twin ? own : shared, mask);
        printRow(sc.name, method.name() + (twin ? " vs itself on " + sc.twinFile : "") + (weak ? " (weak)" : ""), run, &c);
        checkComparison(what, c, weak, sc.medianOfMeansBound);
        if (!weak) others.emplace_back(method, std::move(run));
    }
    if (twin) return;
    // The reference method is not its own reference: its run at the methods' samples is held
    // against the first method that is not weak here, of the other integrator if one is.
    const std::pair<Method, StabilityRun>* judge = nullptr;
    for (const auto& o : others)
        if (!judge || (judge->first.bdpt == sc.reference.bdpt && o.first.bdpt != sc.reference.bdpt)) judge = &o;
    INFO(sc.name << ": no method other than the reference is reliable here, to check the reference against");
    REQUIRE(judge);
    Comparison c = compareRuns(referenceRun, judge->second, mask);
    printRow(sc.name, sc.reference.name() + " vs " + judge->first.name(), referenceRun, &c);
    checkComparison(sc.name + " " + sc.reference.name() + " against " + judge->first.name(), c, nullptr, sc.medianOfMeansBound);
}

}  // namespace brume::test
