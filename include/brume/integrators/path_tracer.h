// The volumetric path tracer (`--integrator pt`): free-flight sampling in every medium
// (homogeneous or grid, grey or coloured), next-event estimation from surface and medium
// vertices MIS-combined (power heuristic) with BSDF/phase sampling, and equi-angular light
// connections on medium segments (`--connect`). It is the reference every other method is
// tested against.
#pragma once
#include <memory>

#include "brume/integrators/connection_shares.h"
#include "brume/integrators/guide_start.h"
#include "brume/integrators/integrator.h"
#include "brume/integrators/path_guide.h"

namespace brume {

struct OneEventSplit;

// How light is connected to medium segments (docs/path-tracer.md):
//  Density:     next-event estimation from the free-flight scatter point;
//  EquiAngular: from a point sampled equi-angularly towards the light on each segment
//               (directional lights keep the free-flight point);
//  Product:     the same, the point sampled by equi-angular × phase (product sampling,
//               equiangular.h) in anisotropic media;
//  Mis:         free-flight and product points, weighted by the power heuristic together
//               with phase sampling.
enum class ConnectMode { Density, EquiAngular, Product, Mis };

// Whether the equi-angular (or product) point replaces the free-flight one.
inline bool variantOnly(ConnectMode m) { return m == ConnectMode::EquiAngular || m == ConnectMode::Product; }

// The anisotropy that equi-angular sampling in a medium of anisotropy g takes into its
// product: g for product and mis, 0 (plain equi-angular) otherwise.
inline float connectAnisotropy(ConnectMode m, float g) {
    return m == ConnectMode::Product || m == ConnectMode::Mis ? g : 0.0f;
}

struct PathTracerOptions {
    int maxDepth = -1;                // most scattering events on a path; −1 = unlimited
    bool nextEventEstimation = true;  // false: pure BSDF/phase sampling (for the tests)
    ConnectMode connect = ConnectMode::Mis;
    // Path guiding (`--guiding on`, docs/path-guiding.md): directions at medium vertices
    // from a field learned in the first passes, MIS-combined with phase sampling.
    bool guiding = false;
    float guideShare = -1;  // ≥ 0: the guided share α in every cell, not learned (tests)
    // Guided distances (guided_distance.h, `--guided-distances`) on the rays leaving
    // vertices up to this many scattering events: 0, the camera rays; −1, none (the
    // default: on the scenes measured they cost more than they gave, docs/path-guiding.md).
    int guidedDistanceDepth = -1;
    // Next-event estimation towards emissive media with emission grids (volume_light_sampling.h,
    // `--volume-lights`); off: their emission is gathered along the rays alone.
    bool volumeLights = true;
    // --connect mis: how often A, C and D are made (connection_shares.h): learned from the first
    // passes of a render (learnShares, the command's default), or these fixed shares (tests;
    // and any sample taken outside a render).
    bool learnShares = false;
    ConnectionShares::Shares shares;
    // `--guiding auto`: no guide at first; one starts before a pass once the render is long
    // enough for it to pay (guide_start.h: plannedPasses, or the time budget's pace), and
    // after the connection shares are learnt. The owner may start it instead (startGuide:
    // auto, once it has chosen the path tracer).
    bool guidingAuto = false;
    int plannedPasses = 0;  // the render's passes where known (`--spp`); 0: not known
};

class PathTracer : public Integrator {
public:
    explicit PathTracer(PathTracerOptions options)
        : options_(options),
          guide_(options.guiding ? std::make_unique<PathGuide>(guideSettings(options)) : nullptr),
          shares_(options.learnShares && options.connect == ConnectMode::Mis && options.nextEventEstimation
                      ? std::make_unique<ConnectionShares>()
                      : nullptr) {}
    Spectrum sample(const Scene& scene, float fx, float fy, int width, int height, Sampler& sampler,
                    PathStats& stats) const override {
        return sample(scene, fx, fy, width, height, sampler, stats, nullptr);
    }
    // The bidirectional tracer's camera family in single scattering (one_event_split.h): the
    // sample with each path camera → medium point → light weighted by the split's W_C.
    Spectrum sample(const Scene& scene, float fx, float fy, int width, int height, Sampler& sampler, PathStats& stats,
                    const OneEventSplit* split) const;
    // --guiding auto: starts the guide before this pass where it pays (guide_start.h).
    void beginPass(const Scene& scene, int pass) override {
        if (options_.guidingAuto && !guide_ && !sharesLearning() && start_.pays(pass)) startGuide();
    }
    void endPass(const Scene& scene, const PassSummary& summary) override {
        if (guide_) guide_->endPass(summary);
        if (shares_) {
            if (shares_->learning()) shares_->keepSegments(pointLikeLightInMedium(scene));  // read at the decision
            shares_->endPass(summary);
        }
        start_.endPass(summary);
    }
    // Starts learning a guide from the next pass on (between passes; once).
    void startGuide() {
        if (!guide_) guide_ = std::make_unique<PathGuide>(guideSettings(options_));
    }
    bool learning(int) const override { return (guide_ && guide_->learning()) || (shares_ && shares_->learning()); }
    void expectPasses(int total) override { start_.expect(total); }
    // Inside the efficiency-aware tracer the shares learn only from the path tracer's own
    // passes (BdptIntegrator::sharesPassAt: its last duel passes, or its first passes once
    // chosen): the pilot's probes neither record nor count. Set between passes.
    void pauseShares(bool paused) { sharesPaused_ = paused; }
    bool sharesLearning() const { return shares_ && shares_->learning(); }
    // The guide's training passes, once the guided ones outnumber them (path_guide.h).
    LeftOutPasses leftOut() const override { return guide_ ? guide_->leftOut() : LeftOutPasses{}; }
    // The guide's state, then the shares' (connection_shares.h) after its length.
    std::string saveState() const override;
    void loadState(const std::string& state) override;
    // The learned connection shares (null unless learned), for --stats.
    const ConnectionShares* connectionShares() const { return shares_.get(); }
    // The guide's cache (null without guiding), for --stats.
    const PathGuide* guide() const { return guide_.get(); }

private:
    // A point, spot or sphere light inside a medium (ConnectionShares::keepSegments).
    static bool pointLikeLightInMedium(const Scene& scene);
    static GuidingSettings guideSettings(const PathTracerOptions& o) {
        GuidingSettings s;
        s.fixedShare = o.guideShare;
        s.inscatter = o.guidedDistanceDepth >= 0;
        return s;
    }
    PathTracerOptions options_;
    std::unique_ptr<PathGuide> guide_;
    std::unique_ptr<ConnectionShares> shares_;
    bool sharesPaused_ = false;
    GuideStart start_{options_.plannedPasses, options_.maxDepth};  // --guiding auto
};

}  // namespace brume
