#include "brume/integrators/bdpt.h"

#include <algorithm>
#include <utility>
#include <stdexcept>
#include <vector>

#include "brume/integrators/allocation_planner.h"
#include "brume/integrators/bdpt_strategies.h"
#include "brume/integrators/bdpt_subpaths.h"
#include "brume/integrators/direct_light_tracing.h"
#include "brume/integrators/one_event_split.h"
#include "brume/integrators/sample_dimensions.h"

namespace brume {

// Notation (docs/mis.md): camera subpath z0 (the pinhole) … z(t−1), light subpath
// y0 (on a light) … y(s−1); strategy (s, t) connects y(s−1) with z(t−1). Every vertex keeps
// pdfFwd (area density of being made by its own walk) and pdfRev (by the other walk); both
// include free-flight densities. A sample: both subpaths, their MIS sums (stored in their
// vertices), then every
// strategy in turn (bdpt_strategies.cpp), each weighted by bdpt_mis.cpp.
namespace {

// One sample's subpaths, kept per thread and reused: a thread holds only the sample in
// flight. (A pass's light subpaths kept together for a light-vertex cache would take
// pixels × mean light-subpath length × sizeof(PathVertex), ~280 B: some 300 MB at 640x480.)
struct Subpaths {
    std::vector<PathVertex> camera = std::vector<PathVertex>(kMaxSubpathVertices);
    std::vector<PathVertex> light = std::vector<PathVertex>(kMaxSubpathVertices);
};

}  // namespace

BdptIntegrator::BdptIntegrator(BdptOptions options)
    : options_(options),
      pathTracer_([&] {
          PathTracerOptions o;
          o.maxDepth = options.maxDepth;
          o.connect = options.connect;
          o.guiding = options.guiding;
          o.guidingAuto = options.guidingAuto && options.efficiencyAware;  // started here (guideStartsAt)
          o.guideShare = options.guideShare;
          o.volumeLights = options.volumeLights;
          // (The fixed tracer's too where it may split single scattering: its camera family is
          // this path tracer, which learns its shares there as `pt` does, beginPass.)
          const bool mayLearnInSplit = !options.efficiencyAware && options.maxDepth == 1 && options.oneEventSplit;
          o.learnShares = options.learnShares && !options.guiding &&
                          (options.efficiencyAware || options.allocation.pathTracer || mayLearnInSplit);
          return o;
      }()),
      guideStart_(options.plannedPasses, options.maxDepth) {
    if (options_.guiding && options_.efficiencyAware)
        throw std::invalid_argument("path guiding takes the path tracer or the bidirectional tracer, not the efficiency-aware one");
    // The fixed tracer with light tracing learns light tracing's share of one-scattering paths
    // (direct_light_tracing.h); so does auto in single scattering, where its duel sets the
    // pilot's allocation with the share against the path tracer (allocation_planner.h). In
    // full transport auto does not: learned in its pilot and applied to the chosen allocation,
    // the factor made the duel keep bidirectional allocations whose tails its eight passes did
    // not show (docs/results.md).
    const bool learnable = options_.directLightTracing < 0 && options_.hooks.onlyS < 0 && !options_.allocation.pathTracer;
    if (options_.efficiencyAware) {
        // (Its statistics need the equi-angular variants to add to the free-flight ones.)
        if (variantOnly(options_.connect))
            throw std::invalid_argument("the efficiency-aware tracer takes --connect mis or density, not equiangular or product");
        planner_ = std::make_unique<AllocationPlanner>(options_.connect, learnable && options_.maxDepth == 1,
                                                       options_.plannedPasses, options_.partialPilot);
        options_.allocation = planner_->allocationFor(0);
    }
    if (planner_ ? planner_->learnedShare() : learnable && options_.allocation.lightSubpaths && options_.allocation.lightTracing)
        direct_ = std::make_unique<DirectLightTracing>();
}

BdptIntegrator::~BdptIntegrator() = default;

bool BdptIntegrator::sharesPassAt(int pass) const {
    if (!pathTracer_.sharesLearning()) return false;
    if (!planner_) return options_.allocation.pathTracer;
    if (planner_->decided()) return planner_->allocationFor(pass).pathTracer;
    // The path tracer's duel passes (kLearningPasses of its kPasses, all of them: made with
    // shares 1, 1, 1, so that the duel measures one estimator, and an aligned block of its
    // Sobol sequence, as the learning's batches need): where it wins, it renders with its
    // shares from the first pass after the duel.
    static_assert(ConnectionShares::kLearningPasses <= AllocationDuel::kPasses, "the shares learn inside the duel");
    return planner_->pathTracerDuelPass(pass, AllocationDuel::kPasses - ConnectionShares::kLearningPasses);
}

// --guiding auto: once the path tracer renders for good (the planner's choice, which it does
// not revisit) and has learnt its shares, where enough passes follow (guide_start.h).
bool BdptIntegrator::guideStartsAt(int pass) const {
    return options_.guidingAuto && planner_ && planner_->decided() && planner_->allocationFor(pass).pathTracer &&
           !pathTracer_.guide() && !pathTracer_.sharesLearning() && guideStart_.pays(pass);
}

bool BdptIntegrator::splitApplies(const Scene& scene) const {
    return options_.oneEventSplit && (!planner_ || planner_->learnedShare()) && options_.maxDepth == 1 && !options_.guiding &&
           options_.hooks.onlyS < 0 && !options_.hooks.observer && options_.allocation == BdptAllocation{} &&
           oneEventSplitApplies(scene);
}

bool BdptIntegrator::checksLightTracing(const Scene& scene) const { return !planner_ && direct_ && splitApplies(scene); }

void BdptIntegrator::beginPass(const Scene& scene, int pass) {
    if (guideStartsAt(pass)) pathTracer_.startGuide();
    guideTraining_ = pathTracer_.guide() && pathTracer_.guide()->training();
    learningDirect_ = !guideTraining_ && direct_ && direct_->learning(pass >= guidePasses() ? pass - guidePasses() : pass);
    usesShare_ = direct_ && (!planner_ || planner_->pilotAllocationAt(pass));
    // Every strategy, in single scattering where the split applies: the fixed tracer, and
    // auto's pilot and duel contender (the pilot's allocation) there. (Not under the hooks,
    // which show and check the generic strategies.)
    splitting_ = splitApplies(scene);
    // The fixed tracer's split: its camera family (the path tracer) learns its connection
    // shares in its first Sobol passes (after light tracing's learning passes, whose numbers
    // are independent: the check's passes), as `pt` does in its first 8.
    sharesPass_ = sharesPassAt(pass) || (!planner_ && splitting_ && !learningDirect_ && pathTracer_.sharesLearning());
    pathTracer_.pauseShares(!sharesPass_);
    // The fixed tracer's split checks light tracing's factor with the render's Sobol numbers.
    checkingDirect_ = splitting_ && !planner_ && direct_ && direct_->checking(pass);
    if (!planner_) return;
    if (direct_) planner_->setLightShare(direct_->subpathShare());
    // The path tracer samples distances by an emitter's solid angle, which the bidirectional
    // tracer does not: only its own samples show what that is worth.
    const bool ownStrategies = options_.connect == ConnectMode::Mis && scene.hasMedia() && scene.hasTriangleLights() &&
                               scene.emitterSampling() == EmitterSampling::SolidAngle;
    planner_->setPathTracerProbe(scene.mediumChannels() > 1 || ownStrategies);
    options_.allocation = planner_->allocationFor(pass);
    collecting_ = planner_->collects(pass) && planner_->ratesCandidates();
    partialPass_ = planner_->partialAt(pass);
}

double BdptIntegrator::lightSubpathsMade() const {
    return usesShare_ && !learningDirect_ && options_.maxDepth == 1 ? direct_->subpathShare() : 1.0;
}

// The learning passes of light tracing's factor sample independently, like the planner's
// pilot (their spread then measures a pass's variance exactly), and take no Sobol index: the
// passes after them start the sequence at 0, whole, when the image leaves them out.
// With guiding, the guide's training passes come first, with sequence indices of their own;
// the bidirectional passes after them start their sequence at 0 (the image leaves the
// training passes out once outnumbered, path_guide.h). (A render that starts its pass count
// again after training, as the tests' batches do, numbers its passes from 0.)
SamplerKind BdptIntegrator::samplerFor(int pass, SamplerKind requested) const {
    if (planner_) return planner_->samplerFor(pass, requested);
    if (guideTraining_) return requested;
    if (pass >= guidePasses()) pass -= guidePasses();
    if (direct_) return pass < DirectLightTracing::kPasses ? SamplerKind::Independent : requested;
    return requested;
}

uint64_t BdptIntegrator::sequenceIndexFor(int pass, SamplerKind kind) const {
    if (planner_) return planner_->sequenceIndex(pass, kind);
    if (guideTraining_) return uint64_t(pass);
    if (pass >= guidePasses()) pass -= guidePasses();
    if (direct_)
        return uint64_t(kind == SamplerKind::Sobol && pass >= DirectLightTracing::kPasses ? pass - DirectLightTracing::kPasses : pass);
    return uint64_t(pass);
}

Integrator::LeftOutPasses BdptIntegrator::leftOut() const {
    // With guiding: the guide's training passes, with light tracing's learning passes when
    // they are left out too (the noise measured by the guide).
    if (options_.guiding) {
        const LeftOutPasses guide = pathTracer_.leftOut();
        if (guide.passes == 0 || !direct_ || direct_->passes() != DirectLightTracing::kPasses) return guide;
        leftOutSums_ = *guide.sums;
        const std::vector<FixedSum>& own = direct_->passSums();
        for (size_t i = 0; i < leftOutSums_.size() && i < own.size(); ++i) leftOutSums_[i] += own[i];
        return LeftOutPasses{guide.passes + direct_->passes(), &leftOutSums_, guide.noise};
    }
    // The learning passes of light tracing's factor, once learned (independent numbers, with
    // c = 1; their noise against the others' is not measured).
    if (!planner_ && direct_ && direct_->passes() == DirectLightTracing::kPasses)
        return LeftOutPasses{direct_->passes(), &direct_->passSums(), 0.0};
    return planner_ ? planner_->leftOut() : LeftOutPasses{};
}

// State: with guiding, "BDG1", the guide's state's length (u64) and the guide's state; where
// the path tracer inside learns connection shares or may start a guide (auto with --guiding
// auto), "BDS1", the length and the path tracer's
// state; then the planner's (auto), then "BDL2" and light tracing's share if it learns one
// (bdpt, and auto in single scattering); with both, the planner's is preceded by its length
// (u64).
bool BdptIntegrator::keepsPathTracerState() const {
    return options_.guiding || pathTracer_.connectionShares() != nullptr || (options_.guidingAuto && planner_);
}

std::string BdptIntegrator::saveState() const {
    if (!keepsPathTracerState()) return saveOwnState();
    std::string out = options_.guiding ? "BDG1" : "BDS1";
    const std::string inside = pathTracer_.saveState();
    putBytes(out, uint64_t(inside.size()));
    return out + inside + saveOwnState();
}

void BdptIntegrator::loadState(const std::string& state) {
    if (!keepsPathTracerState()) return loadOwnState(state);
    const char* what = options_.guiding ? "guiding state is malformed" : "connection shares state is malformed";
    if (state.compare(0, 4, options_.guiding ? "BDG1" : "BDS1") != 0) throw std::runtime_error(what);
    StateReader reader{state, 4};
    const uint64_t n = reader.get<uint64_t>();
    if (n > state.size() - reader.at) throw std::runtime_error(what);
    pathTracer_.loadState(state.substr(reader.at, size_t(n)));
    loadOwnState(state.substr(reader.at + size_t(n)));
}

std::string BdptIntegrator::saveOwnState() const {
    std::string out;
    if (planner_) {
        const std::string planner = planner_->saveState();
        if (!direct_) return planner;
        putBytes(out, uint64_t(planner.size()));
        out += planner;
    }
    if (direct_) {
        out += "BDL2";
        direct_->save(out);
    }
    return out;
}

void BdptIntegrator::loadOwnState(const std::string& state) {
    if (planner_ && !direct_) return planner_->loadState(state);
    if (!direct_) {
        if (!state.empty()) throw std::runtime_error("this integrator keeps no state");
        return;
    }
    StateReader reader{state, 0};
    std::string planner;
    if (planner_) {
        const uint64_t n = reader.get<uint64_t>();
        if (n > state.size() - reader.at) throw std::runtime_error("allocation state is malformed");
        planner = state.substr(reader.at, size_t(n));
        reader.at += size_t(n);
    }
    if (state.compare(reader.at, 4, "BDL2") != 0) throw std::runtime_error("light tracing state is malformed");
    reader.at += 4;
    direct_->load(reader);
    if (reader.at != state.size()) throw std::runtime_error("light tracing state has trailing bytes");
    if (planner_) {
        // (The duel's decision reads the share: known before the planner's state is.)
        planner_->setLightShare(direct_->subpathShare());
        planner_->loadState(planner);
    }
}

Spectrum BdptIntegrator::sampleWithSplats(const Scene& scene, float fx, float fy, int width, int height,
                                          Sampler& sampler, PathStats& stats, SplatList& splats) const {
    if (options_.allocation.pathTracer || guideTraining_) return pathTracer_.sample(scene, fx, fy, width, height, sampler, stats);
    if (splitting_) return sampleSplit(scene, fx, fy, width, height, sampler, stats, splats);
    thread_local Subpaths paths;
    PathVertex* camera = paths.camera.data();
    PathVertex* light = paths.light.data();
    // With --max-depth m, the camera subpath's vertex z(m+1), past the last scattering event,
    // serves only to hit an emitter (s = 0): its ray passes through media (a collision there
    // could serve no strategy), and it is not traced at all when no emitter can be hit.
    const bool limited = options_.maxDepth >= 0;
    const int maxScatter = limited ? options_.maxDepth : kMaxSubpathVertices;
    // (An emissive medium counts as an emitter here: the rays gather it, PathVertex::edgeEmission.)
    const bool hittable = scene.hasHittableLights() || scene.hasEmissiveMedia();
    const int cameraVertices = limited ? maxScatter + (hittable ? 1 : 0) : maxScatter + 1;
    const int passFrom = limited ? maxScatter + 1 : 1 << 30;
    // At the last scattering event z(m) itself, a medium vertex serves only the light
    // connection (s = 1), whose equi-angular variant covers the medium wherever the light has
    // a position: there the walk passes through too and reaches the surface behind with
    // weight T, and the in-scattering comes from the connections alone. (Not past invisible
    // boundaries, where a medium vertex has no equi-angular variant; nor in auto's pilot,
    // whose statistics rate allocations without that variant, except where it learns light
    // tracing's share, allocation_planner.h.)
    const int passFirstAt = limited && maxScatter >= 1 && options_.connect != ConnectMode::Density &&
                                    options_.allocation.equiAngularLight && (!options_.efficiencyAware || planner_->learnedShare()) &&
                                    !scene.hasInvisibleBoundaries() && !scene.hasDirectionalLights() &&
                                    !scene.hasEmissiveMedia()
                                ? maxScatter
                                : 1 << 30;
    // In coloured media both walks sample distances with one hero channel, drawn uniformly;
    // the weights are taken over the channels as well as the strategies (bdpt_mis.h).
    const int channels = scene.mediumChannels();
    const int hero = channels > 1 ? std::min(channels - 1, int(sampler.get1D(dim::kHeroChannel) * channels)) : 0;
    const uint64_t rays0 = stats.rays;
    // Guided directions and survival of the camera walk, after the guide's training passes.
    const PathGuide* guide = options_.guiding ? pathTracer_.guide() : nullptr;
    const GuidingField* field = guide ? guide->field() : nullptr;
    const uint32_t pixel = uint32_t(std::min(std::max(int(fy), 0), height - 1)) * uint32_t(width) +
                           uint32_t(std::min(std::max(int(fx), 0), width - 1));
    // Volume lights (volume_light_sampling.h) from the camera walk's vertices up to the last
    // scattering event, in scenes without coloured media (the weights against the gathering
    // are then over two strategies alone, not over channels too).
    const int volumeLightsUpTo = options_.volumeLights && !scene.volumeLights().empty() && channels == 1 &&
                                         options_.hooks.onlyS < 0
                                     ? maxScatter
                                     : 0;
    // The transparent emitters its rays cross (emitter_crossing.h).
    thread_local std::vector<CrossingVertex> crossings;
    crossings.clear();
    // auto's partial pilot passes: a pixel that does not record makes its light subpath's
    // camera connections alone, towards the recording pixels (AllocationPlanner::partialAt),
    // and counts its rays apart (PathStats::partialLight).
    const int px = int(fx), py = int(fy);
    const bool lightSideOnly = partialPass_ && !AllocationPlanner::collectsPixel(px, py);
    thread_local PathCounts recordingCounts;  // (no per-sample construction)
    if (lightSideOnly) {
        recordingCounts = stats.counts;
        stats.counts = PathCounts{};
    }
    const int nCamera = lightSideOnly
                            ? cameraVertexOnly(scene, fx, fy, width, height, camera)
                            : traceCameraSubpath(scene, fx, fy, width, height, cameraVertices, passFrom, passFirstAt, hero,
                                                 sampler, camera, stats, field,
                                                 field ? guide->pixelEstimate(pixel, width, height) : -1.0f,
                                                 options_.heuristic, volumeLightsUpTo,
                                                 scene.hasTransparentEmitters() ? &crossings : nullptr);
    const uint64_t rays1 = stats.rays;
    // The light subpaths of a pass splat all over the image: their numbers come from one
    // sequence for the image (Sampler::imageWide), so that with Sobol a pass's light subpaths
    // are stratified over the light's emission and the image they reach.
    const Sampler lightSampler = sampler.imageWide(uint64_t(std::min(int(fy), height - 1)) * uint64_t(width) +
                                                       uint64_t(std::min(int(fx), width - 1)),
                                                   uint64_t(width) * uint64_t(height));
    // In single scattering light subpaths serve light tracing alone: made as often as its
    // learned share (lightSubpathsMade), chosen by a number of the image-wide sequence.
    const double lightMade = lightSubpathsMade();
    const bool traced = options_.allocation.lightSubpaths && (lightMade >= 1.0 || lightSampler.get1D(dim::kLightStart + dim::kMade) < lightMade);
    const int nLight = traced ? traceLightSubpath(scene, maxScatter, hero, lightSampler, light, stats, field) : 0;
    stats.counts.bdpt.cameraWalkRays += rays1 - rays0;
    stats.counts.bdpt.lightWalkRays += stats.rays - rays1;

    const bool weighted = options_.hooks.onlyS < 0 || options_.hooks.weighted;
    MisSettings mis{options_.heuristic, options_.connect,       options_.exactEquiAngular,
                    options_.generalEquiAngular, options_.allocation.generalConnection, width, height, channels, hero,
                    passFrom, passFirstAt};
    mis.generalConnection = options_.allocation.lightSubpaths ? options_.allocation.generalConnection : 0.0;
    mis.cameraConnection = options_.allocation.lightSubpaths && options_.allocation.lightTracing ? lightMade : 0.0;
    mis.equiAngularLight = options_.allocation.equiAngularLight;
    mis.equiAngularCamera = options_.allocation.equiAngularCamera;
    mis.equiAngularOnly = options_.allocation.equiAngularOnly;
    mis.cameraGuide = field;
    if (usesShare_) mis.directLightTracing = direct_->factor();
    else if (options_.directLightTracing >= 0) mis.directLightTracing = options_.directLightTracing;
    if (weighted) {
        misPrefixes(scene, camera, nCamera, true, mis);
        misPrefixes(scene, light, nLight, false, mis);
    }
    // The efficiency-aware tracer's statistics passes: every second pixel records its
    // contributions, whose second moments under each candidate are summed after the sample.
    const bool collect = collecting_ && weighted && AllocationPlanner::collectsPixel(px, py);
    thread_local std::vector<WeightRecord> records;
    records.clear();
    // direct_light_tracing.h's learning passes: one-event paths weighted per family alone too.
    Spectrum directCamera(0.0f);
    const bool learning = learningDirect_ && weighted;
    if (learning) direct_->ensureImages(width, height);
    TechniqueSample techniques;
    const StrategyContext c{scene,  options_, mis,   camera, nCamera, light, nLight, weighted,
                            sampler, stats,   width, height, collect ? &records : nullptr,
                            learning ? direct_.get() : nullptr, &directCamera, &techniques, lightSideOnly};

    // What the camera walk's rays gathered from emissive media: paths no other strategy makes.
    Spectrum L = options_.hooks.onlyS < 0 && !lightSideOnly ? mediumEmission(c) : Spectrum(0.0f);
    if (volumeLightsUpTo > 0 && !lightSideOnly) L += volumeLightConnections(c, volumeLightsUpTo);
    // t = nCamera + 1 exists only for equi-angular vertices on the walk's last, escaped ray;
    // likewise s = nLight + 1 for equi-angular camera connections on the light walk's.
    const bool anyEquiAngular = options_.connect != ConnectMode::Density;
    for (int t = 1; t <= nCamera + (anyEquiAngular ? 1 : 0); ++t) {
        // (A subpath that filled its array has no slot after it, so no ray record.)
        if (lightSideOnly && t > 1) break;  // (z0 alone: camera connections only)
        if (t > nCamera && (nCamera >= kMaxSubpathVertices || !camera[t - 1].ghost)) break;
        // s = 1 draws a fresh light sample, so it runs even when the light subpath is empty.
        for (int s = 0; s <= std::max(nLight, 1) + (anyEquiAngular && t == 1 ? 1 : 0); ++s) {
            if (s == 0 && t < 2) continue;
            if (t == 1 ? mis.cameraConnection == 0 : s >= 2 && mis.generalConnection == 0) continue;
            if (options_.maxDepth >= 0 && s + t - 2 > options_.maxDepth) continue;
            if (options_.hooks.onlyS >= 0 && (s != options_.hooks.onlyS || t != options_.hooks.onlyT)) continue;
            // Past the camera walk's end only an equi-angular variant has a vertex: the light
            // connection's, and general connections' when they have variants.
            if (t > nCamera && s != 1 && !options_.generalEquiAngular) continue;
            if ((t == 1 || s > 1) && s > nLight &&
                !(t == 1 && s == nLight + 1 && s >= 2 && nLight < kMaxSubpathVertices && light[s - 1].ghost))
                continue;
            if (s == 0) {
                L += emitterHit(c, t);
            } else if (t == 1) {
                cameraConnection(c, s, splats);
            } else if (s == 1) {
                L += lightConnection(c, t);
            } else {
                L += subpathConnection(c, s, t);
            }
        }
    }
    for (const CrossingVertex& x : crossings) {  // s = 0 on each, t = its index + 1
        const int t = x.index + 1;
        if (options_.maxDepth >= 0 && t - 2 > options_.maxDepth) continue;
        if (options_.hooks.onlyS >= 0 && (options_.hooks.onlyS != 0 || options_.hooks.onlyT != t)) continue;
        L += crossedEmitterHit(c, x);
    }
    if (learning) direct_->addCamera(std::min(px, width - 1), std::min(py, height - 1), directCamera);
    techniques.addTo(stats.techniques);
    if (collect) {
        const int ox = std::min(px, width - 1), oy = std::min(py, height - 1);
        accumulateMoments(scene, camera, nCamera, light, nLight, mis, planner_->candidates(), records, planner_->weights(),
                          ox, oy, stats.moments, planner_->ownParts(ox, oy));
        // In coloured media and where the path tracer has strategies of its own, its probe:
        // one sample of its own, kept out of the image (allocation_planner.h).
        const TechniqueSums kept = stats.techniques;  // (the probe is not in the image)
        const Spectrum probe = planner_->pathTracerProbe() ? pathTracer_.sample(scene, fx, fy, width, height, sampler, stats) : Spectrum(0.0f);
        stats.techniques = kept;
        const float* w = planner_->weights().at(ox, oy);
        if (isFinite(probe))
            for (int ch = 0; ch < 3; ++ch) {
                stats.moments.probe += double(w[ch]) * double(probe[ch]) * double(probe[ch]);
                stats.moments.probeMean += double(w[ch]) * double(probe[ch]);
            }
    }
    if (lightSideOnly) {
        stats.partialLight.add(stats.counts);
        stats.counts = recordingCounts;
    }
    return L;
}

const LightPixels* BdptIntegrator::lightPixelsFor(const Scene& scene, int width, int height) const {
    const LightPixels* t = lightPixels_.load(std::memory_order_acquire);
    if (t && t->madeFor(&scene, width, height)) return t;
    std::lock_guard<std::mutex> lock(lightPixelsMaking_);
    t = lightPixels_.load(std::memory_order_acquire);
    if (t && t->madeFor(&scene, width, height)) return t;
    lightPixelTables_.push_back(std::make_unique<LightPixels>(scene, width, height));
    t = lightPixelTables_.back().get();
    lightPixels_.store(t, std::memory_order_release);
    return t;
}

// The camera family: the path tracer's sample with W_C; the light family: light tracing, made
// with probability q by a number of the image-wide sequence (as the light subpaths of the
// generic tracer), with W_L; κ and q as the generic tracer has them (direct_light_tracing.h).
Spectrum BdptIntegrator::sampleSplit(const Scene& scene, float fx, float fy, int width, int height, Sampler& sampler,
                                     PathStats& stats, SplatList& splats) const {
    OneEventSplit split;
    split.lightPixels = lightPixelsFor(scene, width, height);
    split.mode = options_.connect;
    split.width = width;
    split.height = height;
    split.q = lightSubpathsMade();
    split.kappa = usesShare_ ? direct_->factor() : options_.directLightTracing >= 0 ? options_.directLightTracing : 1.0;
    const int px = std::min(int(fx), width - 1), py = std::min(int(fy), height - 1);
    Spectrum alone(0.0f), weighted(0.0f);
    const bool gathering = learningDirect_ || checkingDirect_;
    if (gathering) {
        direct_->ensureImages(width, height);
        split.cameraAlone = &alone;
    }
    if (checkingDirect_) split.cameraSplit = &weighted;
    split.atCameraRay(fx, fy);
    const Spectrum L = pathTracer_.sample(scene, fx, fy, width, height, sampler, stats, &split);
    if (split.q > 0) {  // (light tracing turned off: none, direct_light_tracing.h)
        const Sampler lightSampler =
            sampler.imageWide(uint64_t(py) * uint64_t(width) + uint64_t(px), uint64_t(width) * uint64_t(height));
        if (split.q >= 1 || lightSampler.get1D(dim::kLightStart + dim::kMade) < split.q)
            oneEventLightTracing(scene, split, lightSampler, stats, splats, gathering ? direct_.get() : nullptr);
    }
    if (gathering) direct_->addCamera(px, py, alone);
    if (checkingDirect_) direct_->addSplitCamera(px, py, weighted);
    return L;
}

bool BdptIntegrator::learning(int pass) const {
    if ((options_.guiding || pathTracer_.guide()) && pathTracer_.learning(pass)) return true;
    if (guideStartsAt(pass)) return true;
    if (direct_ && direct_->learning(pass >= guidePasses() ? pass - guidePasses() : pass)) return true;
    if (splitting_ && !planner_ && direct_ && direct_->checking(pass)) return true;
    if (sharesPassAt(pass)) return true;
    return planner_ && !planner_->decided();
}

void BdptIntegrator::endPass(const Scene& scene, const PassSummary& summary) {
    guideStart_.endPass(summary);
    // The guide's training, then the noise of the passes after it; the shares' learning.
    if (pathTracer_.guide() || sharesPass_) pathTracer_.endPass(scene, summary);
    if (guideTraining_ && !planner_) return;
    if (learningDirect_) summary.complete ? direct_->endPass(summary) : direct_->discardPass();
    if (checkingDirect_) summary.complete ? direct_->endCheckPass(&summary.totals.counts, options_.plannedPasses) : direct_->discardPass();
    if (planner_) {
        if (direct_) planner_->setLightShare(direct_->subpathShare());
        planner_->endPass(summary);
    }
    if (!summary.complete) return;
    for (int k = 0; k < 4; ++k) {
        lastPass_.freeFlight[k] = summary.totals.counts.bdpt.contribution(StrategyKind(k), false);
        lastPass_.equiAngular[k] = summary.totals.counts.bdpt.contribution(StrategyKind(k), true);
        total_.freeFlight[k] += lastPass_.freeFlight[k];
        total_.equiAngular[k] += lastPass_.equiAngular[k];
    }
}

}  // namespace brume
