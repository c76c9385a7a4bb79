#include "brume/render/renderer.h"

#include "brume/film/pixel_noise.h"
#include "brume/integrators/sample_dimensions.h"
#include "brume/sampling/inverse_distance.h"
#include "brume/scene/light_pixels.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace brume {

namespace {

constexpr int kTileSize = 16;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Counters of one tile in the current pass; summed only when the pass completes, so a
// dropped pass leaves no trace in the statistics either. A cache line each: workers count
// every ray into their tile's counters, and neighbouring tiles are rendered at the same time
// (sharing a line slowed cheap rays down by up to a quarter on 2 threads).
struct alignas(64) TileCounters {
    uint64_t samples = 0;
    uint64_t nonFinite = 0;
    PathStats path;
};

class ProgressBar {
public:
    explicit ProgressBar(bool enabled) : enabled_(enabled) {}
    // With a noise threshold: the estimated relative error now (√ of the mean e²), the
    // share of pixels still going on and the seconds left (< 0: not known), shown after the
    // bar.
    void setNoise(double error, double activeShare, double secondsLeft) {
        noise_ = error;
        activeShare_ = activeShare;
        secondsLeft_ = secondsLeft;
    }
    void show(double fraction, int passesDone, const RenderOptions& options, double seconds) {
        if (!enabled_) return;
        if (options.noiseThreshold > 0 && noise_ >= 0) {
            char left[48] = "";
            if (secondsLeft_ >= 0) std::snprintf(left, sizeof left, ", about %.0f s left", secondsLeft_);
            if (options.noiseWholeImage)
                std::fprintf(stderr, "\r[noise %.3g / %.3g]  pass %d  %.1f s%s   ", noise_, options.noiseThreshold,
                             passesDone, seconds, left);
            else
                std::fprintf(stderr, "\r[noise %.3g / %.3g, %3.0f%% of pixels going on]  pass %d  %.1f s%s   ", noise_,
                             options.noiseThreshold, 100 * activeShare_, passesDone, seconds, left);
            std::fflush(stderr);
            shown_ = true;
            return;
        }
        fraction = std::clamp(fraction, 0.0, 1.0);
        constexpr int kWidth = 30;
        int filled = int(fraction * kWidth);
        char bar[kWidth + 1];
        for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
        bar[kWidth] = '\0';
        if (options.timeBudget > 0)
            std::fprintf(stderr, "\r[%s] %3d%%  %d passes  %.1f / %.1f s ", bar, int(fraction * 100), passesDone,
                         seconds, options.timeBudget);
        else if (fraction > 0 && fraction < 1)  // the time left at this pace
            std::fprintf(stderr, "\r[%s] %3d%%  pass %d/%d  %.1f s, about %.0f s left ", bar, int(fraction * 100),
                         passesDone, options.spp, seconds, seconds * (1 - fraction) / fraction);
        else
            std::fprintf(stderr, "\r[%s] %3d%%  pass %d/%d  %.1f s              ", bar, int(fraction * 100),
                         passesDone, options.spp, seconds);
        std::fflush(stderr);
        shown_ = true;
    }
    void finish() {
        if (enabled_ && shown_) std::fputc('\n', stderr);
    }

private:
    bool enabled_;
    bool shown_ = false;
    double noise_ = -1, activeShare_ = 1, secondsLeft_ = -1;
};

// The largest float below 1: a film position stays inside its pixel.
constexpr float kBelowOne = 0x1.fffffep-1f;

// The worker pool for one render() call.
class PassRunner {
public:
    PassRunner(const Scene& scene, Integrator& integrator, const RenderOptions& options, Film& film,
               int threadCount, const std::atomic<bool>* drop)
        : scene_(scene),
          integrator_(integrator),
          splatter_(dynamic_cast<const SplattingIntegrator*>(&integrator)),
          options_(options),
          film_(film),
          drop_(drop),
          tilesX_((options.width + kTileSize - 1) / kTileSize),
          tilesY_((options.height + kTileSize - 1) / kTileSize),
          radiance_(size_t(options.width) * size_t(options.height)),
          tileCounters_(size_t(tileCount())),
          lightPixels_(scene, options.lightPixels ? options.width : 0, options.lightPixels ? options.height : 0) {
        if (splatter_) tileSplats_.resize(size_t(tileCount()));
        threads_.reserve(threadCount);
        try {
            for (int i = 0; i < threadCount; ++i) threads_.emplace_back([this] { workerLoop(); });
        } catch (...) {
            stop();
            throw;
        }
    }
    ~PassRunner() { stop(); }

    int tileCount() const { return tilesX_ * tilesY_; }
    int tilesDone() const { return tilesDone_.load(std::memory_order_relaxed); }

    // Starts pass `pass` on all workers and returns at once; `active` (null: every pixel)
    // names the pixels that take part, `activeCount` of them; `droppable`: the pass may be
    // abandoned (RenderControl::dropInFlight).
    void startPass(int pass, const std::vector<uint8_t>* active, int activeCount, bool droppable) {
        integrator_.beginPass(scene_, pass);
        passStart_ = Clock::now();
        std::lock_guard<std::mutex> lock(mutex_);
        droppable_ = droppable;
        active_ = active;
        activeCount_ = activeCount;
        pass_ = pass;
        passSampler_ = integrator_.samplerFor(pass, options_.sampler);
        passIndex_ = integrator_.sequenceIndexFor(pass, passSampler_);
        nextTile_.store(0);
        tilesDone_.store(0);
        running_ = int(threads_.size());
        ++generation_;
        startCv_.notify_all();
    }
    // Waits up to `timeout` for the pass to finish; true once it has.
    bool waitPass(std::chrono::milliseconds timeout) {
        std::unique_lock<std::mutex> lock(mutex_);
        return doneCv_.wait_for(lock, timeout, [this] { return running_ == 0; });
    }
    // After the workers stopped: rethrows a worker's exception; if every tile was rendered,
    // adds the pass to the film (samples in pixel order, splats in tile order), adds its
    // counters to `stats` and returns true; otherwise (dropped) returns false.
    bool finishPass(RenderStats& stats) {
        if (error_) std::rethrow_exception(error_);
        const bool complete = tilesDone() == tileCount();
        PassSummary summary;
        summary.pass = pass_;
        summary.complete = complete;
        summary.seconds = secondsSince(passStart_);
        summary.timeBudget = options_.timeBudget;
        if (complete) {
            const int width = options_.width;
            for (int y = 0; y < options_.height; ++y)
                for (int x = 0; x < width; ++x)
                    if (!active_ || (*active_)[size_t(y) * size_t(width) + size_t(x)])
                        film_.add(x, y, radiance_[size_t(y) * size_t(width) + size_t(x)]);
            for (const TileCounters& c : tileCounters_) {
                stats.samples += c.samples;
                stats.nonFinite += c.nonFinite;
                summary.totals.add(c.path);
            }
            stats.rays += summary.totals.rays;
            stats.counts.add(summary.totals.counts);
            stats.techniques.add(summary.totals.techniques);
            summary.width = options_.width;
            summary.height = options_.height;
            summary.radiance = radiance_.data();
            summary.splats = tileSplats_.data();
            summary.splatLists = int(tileSplats_.size());
        }
        if (complete) {
            if (film_.tracksNoise()) passTotal_ = radiance_;
            // Each pixel that took part traced one light subpath: their splats estimate the
            // image scaled by the share that did (1 while every pixel takes part).
            const float scale = active_ ? float(double(options_.width) * double(options_.height) / activeCount_) : 1.0f;
            for (SplatList& list : tileSplats_) {
                stats.nonFinite += list.nonFinite();
                for (const SplatList::Record& r : list.records()) {
                    const size_t i = size_t(r.y) * size_t(options_.width) + size_t(r.x);
                    if (active_ && !(*active_)[i]) continue;
                    const Spectrum value = active_ ? r.value * scale : r.value;
                    film_.splat(r.x, r.y, value);
                    if (film_.tracksNoise()) passTotal_[i] += value;
                }
            }
            if (film_.tracksNoise())
                for (size_t i = 0; i < passTotal_.size(); ++i)
                    if (!active_ || (*active_)[i]) film_.addPassValue(i, passTotal_[i]);
        }
        integrator_.endPass(scene_, summary);
        for (SplatList& list : tileSplats_) list.clear();
        return complete;
    }

private:
    void stop() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            quit_ = true;
            startCv_.notify_all();
        }
        for (std::thread& t : threads_)
            if (t.joinable()) t.join();
    }

    void workerLoop() {
        // Embree asks for these in every thread that traces rays.
        _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
        _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
        uint64_t seen = 0;
        for (;;) {
            int pass;
            {
                std::unique_lock<std::mutex> lock(mutex_);
                startCv_.wait(lock, [&] { return quit_ || generation_ != seen; });
                if (quit_) return;
                seen = generation_;
                pass = pass_;
            }
            try {
                for (int t = nextTile_.fetch_add(1); t < tileCount(); t = nextTile_.fetch_add(1)) {
                    if (drop_ && droppable_ && drop_->load(std::memory_order_relaxed)) break;
                    renderTile(t, pass);
                    tilesDone_.fetch_add(1, std::memory_order_relaxed);
                }
            } catch (...) {
                std::lock_guard<std::mutex> lock(mutex_);
                if (!error_) error_ = std::current_exception();
                nextTile_.store(tileCount());  // the others stop after their current tile
            }
            std::lock_guard<std::mutex> lock(mutex_);
            if (--running_ == 0) doneCv_.notify_all();
        }
    }

    void renderTile(int tile, int pass) {
        const int width = options_.width, height = options_.height;
        const int x0 = (tile % tilesX_) * kTileSize, y0 = (tile / tilesX_) * kTileSize;
        const int x1 = std::min(x0 + kTileSize, width), y1 = std::min(y0 + kTileSize, height);
        TileCounters& counters = tileCounters_[size_t(tile)];
        counters = TileCounters();
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                if (active_ && !(*active_)[size_t(y) * size_t(width) + size_t(x)]) {
                    radiance_[size_t(y) * size_t(width) + size_t(x)] = Spectrum(0.0f);
                    continue;
                }
                Sampler sampler(options_.seed, uint64_t(y) * uint64_t(width) + uint64_t(x), passIndex_, passSampler_);
                Sample2 jitter = sampler.get2D(dim::kFilmJitter);
                // Where a point light in fog is imaged, the film position is drawn in
                // proportion to 1/(distance to the image) from the same numbers, and the
                // camera side's value weighted 1/p = Z·|x − c| (the pixel's area is 1):
                // uniform positions give that pixel infinite variance (inverse_distance.h).
                // Splats are the light side's own samples and keep their values.
                float filmWeight = 1;
                if (const LightPixel* lp = lightPixels_.find(uint32_t(y) * uint32_t(width) + uint32_t(x))) {
                    const InverseDistanceSample s = sampleInverseDistance(lp->cx, lp->cy, jitter);
                    jitter = Sample2{std::min(s.x, kBelowOne), std::min(s.y, kBelowOne)};
                    filmWeight = s.weight;
                }
                const float fx = float(x) + jitter.u, fy = float(y) + jitter.v;
                Spectrum L = splatter_ ? splatter_->sampleWithSplats(scene_, fx, fy, width, height, sampler,
                                                                     counters.path, tileSplats_[size_t(tile)])
                                       : integrator_.sample(scene_, fx, fy, width, height, sampler, counters.path);
                // (A weight of 0, the image itself, is a point of measure zero: its value may
                // be unbounded there and is not counted.)
                if (filmWeight != 1) L = filmWeight > 0 ? L * filmWeight : Spectrum(0.0f);
                ++counters.samples;
                // A dropped sample adds +0, which leaves every sum as it was (sums start at +0
                // and so are never -0, the one value x + 0 changes).
                if (!isFinite(L)) {
                    ++counters.nonFinite;
                    L = Spectrum(0.0f);
                }
                radiance_[size_t(y) * size_t(width) + size_t(x)] = L;
            }
    }

    const Scene& scene_;
    Integrator& integrator_;
    const SplattingIntegrator* splatter_;
    const RenderOptions& options_;
    Film& film_;
    const std::atomic<bool>* drop_;       // non-null: abandon the pass once it is true
    bool droppable_ = true;               // this pass may be abandoned
    const int tilesX_, tilesY_;
    std::vector<Spectrum> radiance_;      // the pass in flight, one sample per pixel
    std::vector<Spectrum> passTotal_;     // with noise tracking: its samples and splats per pixel
    const std::vector<uint8_t>* active_ = nullptr;  // the pixels taking part (null: all)
    int activeCount_ = 0;
    std::vector<TileCounters> tileCounters_;
    const LightPixels lightPixels_;  // where the film position is drawn by inverse distance
    std::vector<SplatList> tileSplats_;   // one per tile, merged in tile order
    std::vector<std::thread> threads_;

    std::mutex mutex_;
    std::condition_variable startCv_, doneCv_;
    uint64_t generation_ = 0;  // bumped for every pass
    int pass_ = 0;
    SamplerKind passSampler_ = SamplerKind::Sobol;  // Integrator::samplerFor the pass in flight
    uint64_t passIndex_ = 0;                        // and its sequenceIndexFor
    Clock::time_point passStart_;
    int running_ = 0;          // workers still in the current pass
    bool quit_ = false;
    std::exception_ptr error_;
    std::atomic<int> nextTile_{0};
    std::atomic<int> tilesDone_{0};
};

}  // namespace

RenderStats render(const Scene& scene, Integrator& integrator, const RenderOptions& options, Film& film,
                   const RenderControl& control) {
    if (options.width != film.width() || options.height != film.height())
        throw std::invalid_argument("render size " + std::to_string(options.width) + "x" +
                                    std::to_string(options.height) + " does not match the film (" +
                                    std::to_string(film.width()) + "x" + std::to_string(film.height()) + ")");
    if (options.firstPass >= 0 && options.passStride < 1)
        throw std::invalid_argument("passStride must be at least 1, got " + std::to_string(options.passStride));
    if (options.timeBudget <= 0 && options.spp < 1)
        throw std::invalid_argument("spp must be at least 1, got " + std::to_string(options.spp));
    if (!(options.timeBudget >= 0) || options.timeBudget > 1e9)
        throw std::invalid_argument("time budget must be a non-negative number of seconds");
    if (options.threads < 0) throw std::invalid_argument("thread count must not be negative");
    const bool adaptive = options.noiseThreshold > 0;
    if (!(options.noiseThreshold >= 0) || options.noiseThreshold > 1e9)
        throw std::invalid_argument("noise threshold must be a non-negative number");
    if (adaptive && options.firstPass >= 0)
        throw std::invalid_argument("adaptive stopping renders every pass in one process (no firstPass)");
    if (adaptive && !film.tracksNoise()) {
        if (film.passes() > 0) throw std::invalid_argument("adaptive stopping needs a film that tracked noise from its first pass");
        film.trackNoise();
    }

    // More workers than tiles would only wait at the barrier.
    const int tiles = ((options.width + kTileSize - 1) / kTileSize) * ((options.height + kTileSize - 1) / kTileSize);
    int threadCount = options.threads > 0 ? options.threads : int(std::thread::hardware_concurrency());
    threadCount = std::clamp(threadCount, 1, tiles);

    RenderStats stats;
    const Clock::time_point start = Clock::now();
    ProgressBar progress(options.progress);
    auto cancelled = [&] { return control.cancel && control.cancel->load(); };
    // Neither a time budget nor a cancel ends a render of the film's next passes, nor drops
    // a pass in flight, where its image would have partial passes alone: auto's partial pilot
    // passes (Integrator::LeftOutPasses::partialPasses), which the image leaves out, so it
    // goes on to the first pass after them. (A count of passes is what it says: auto takes
    // partial passes only in renders planned to be long, BdptOptions::partialPilot.)
    auto whole = [&] {
        const Integrator::LeftOutPasses out = integrator.leftOut();
        return options.firstPass >= 0 || !out.partialSums || film.passes() > out.partialPasses;
    };
    // A time budget ends at the budget, or sooner on a block of Sobol passes
    // (RenderOptions::sobolBlocks): at a count of the image's passes that ends a block, where
    // the next block's passes would not fit in the budget at the slower of this call's pace so
    // far and its pace since the last block, with a tenth to spare. (At the average pace alone
    // a slower stretch, or an integrator whose first passes are cheap, made a block that did
    // not fit: the budget then ended 1–3 passes past a block, at 3× the error: bdpt, fog room,
    // single scattering, two seeds of four.)
    double markSeconds = 0;
    int markPasses = 0;
    auto enough = [&] {
        if (options.timeBudget <= 0) return stats.passes >= options.spp;
        const double t = secondsSince(start);
        if (t >= options.timeBudget) return whole();
        if (!options.sobolBlocks || options.sampler != SamplerKind::Sobol || adaptive || !whole()) return false;
        const int n = imagePasses(film, integrator, options.sampler), block = sobolBlock(n);
        if (!(n > 0 && n % block == 0) || stats.passes <= markPasses) return false;
        const double pace = std::max(t / stats.passes, (t - markSeconds) / (stats.passes - markPasses));
        markSeconds = t;
        markPasses = stats.passes;
        return t + 1.1 * pace * block > options.timeBudget;
    };
    // Adaptive stopping: the pixels taking part in the next pass, decided from the film alone
    // (and the integrator's learning, itself restored with a checkpoint).
    std::vector<uint8_t> active;
    double secondsLeft = -1, leftAt = 0;
    auto decide = [&](int pass) -> const std::vector<uint8_t>* {
        if (!adaptive) return nullptr;
        const int maxPasses = options.timeBudget > 0 ? 0 : film.passes() + options.spp - stats.passes;
        // The whole image's rule tells the integrator how long the render is expected to be
        // (a guide starts only where enough passes follow: guide_start.h), before it asks
        // whether this pass learns.
        NoiseState noise;
        if (options.noiseWholeImage) {
            noise = activePixels(film, 0.0, active);
            integrator.expectPasses(expectedPasses(film.passes(), noise.meanSquared, options.noiseThreshold, maxPasses));
            if (!integrator.learning(pass)) noise = imageDecision(film.passes(), noise, options.noiseThreshold, active, maxPasses);
        } else {
            noise = activePixels(film, integrator.learning(pass) ? 0.0 : options.noiseThreshold, active, maxPasses);
        }
        stats.activePixels = noise.active;
        stats.estimatedRelMse = noise.meanSquared;
        // The time left at this render's pace per pixel sample, estimated at decisions and
        // counted down in between.
        const double now = secondsSince(start);
        if (noise.samplesLeft >= 0 && stats.samples > 0 && options.timeBudget <= 0) {
            secondsLeft = noise.samplesLeft * now / double(stats.samples);
            leftAt = now;
        }
        progress.setNoise(std::isfinite(noise.meanSquared) ? std::sqrt(noise.meanSquared) : -1,
                          double(noise.active) / double(active.size()),
                          secondsLeft >= 0 ? std::max(0.0, secondsLeft - (now - leftAt)) : -1);
        return noise.active == int(active.size()) ? nullptr : &active;
    };
    {
        PassRunner runner(scene, integrator, options, film, threadCount,
                          control.dropInFlight ? control.cancel : nullptr);
        for (;;) {
            if (stats.passes > 0 && enough()) break;
            if (cancelled() && (stats.passes > 0 || control.dropInFlight) && whole()) break;
            // The pass's index (its sampler key): the film's next one, or this call's share.
            const int pass = options.firstPass >= 0 ? options.firstPass + stats.passes * options.passStride : film.passes();
            const std::vector<uint8_t>* taking = decide(pass);
            if (adaptive && stats.activePixels == 0) break;  // every pixel reached the threshold
            runner.startPass(pass, taking, stats.activePixels, whole());
            while (!runner.waitPass(std::chrono::milliseconds(200))) {
                double t = secondsSince(start);
                double fraction = options.timeBudget > 0
                                      ? t / options.timeBudget
                                      : (stats.passes + double(runner.tilesDone()) / runner.tileCount()) / options.spp;
                progress.show(fraction, stats.passes, options, t);
            }
            if (!runner.finishPass(stats)) break;  // dropped
            film.completePass();
            ++stats.passes;
            double t = secondsSince(start);
            progress.show(options.timeBudget > 0 ? t / options.timeBudget : double(stats.passes) / options.spp,
                          stats.passes, options, t);
            if (control.afterPass) {
                stats.seconds = t;
                control.afterPass(film, stats);
            }
        }
    }
    if (adaptive) decide(film.passes());  // the state after the last pass, for the report
    stats.seconds = secondsSince(start);
    progress.finish();
    return stats;
}

RenderStats render(const Scene& scene, Integrator& integrator, const RenderOptions& options, Film& film,
                   const std::atomic<bool>* cancel) {
    RenderControl control;
    control.cancel = cancel;
    return render(scene, integrator, options, film, control);
}

namespace {
// Whether the image leaves out the passes `out` names, beside n others (finalImage).
bool leavesOut(const Integrator::LeftOutPasses& out, int n, SamplerKind sampler) {
    if (out.always) return true;
    const bool noisier = out.noise > 2.0 + double(out.passes) / n;
    const bool outnumbered = sampler == SamplerKind::Sobol && n >= kLeftOutRatio * out.passes;
    return noisier || outnumbered;
}
}  // namespace

int imagePasses(const Film& film, const Integrator& integrator, SamplerKind sampler) {
    const Integrator::LeftOutPasses out = integrator.leftOut();
    const int partial = out.partialSums ? out.partialPasses : 0;
    const int others = film.passes() - out.passes - partial;
    const bool group = out.passes > 0 && out.sums && others > 0;
    return film.passes() - partial - (group && leavesOut(out, others, sampler) ? out.passes : 0);
}

int sobolBlock(int n) {
    int top = 0;
    while (top < 30 && (2 << top) <= n) ++top;  // 2^top ≤ n < 2^(top + 1)
    return top >= 2 ? 1 << (top - 2) : 1;
}

std::vector<float> finalImage(const Film& film, const Integrator& integrator, SamplerKind sampler) {
    const Integrator::LeftOutPasses out = integrator.leftOut();
    const int partial = out.partialSums ? out.partialPasses : 0;
    const int others = film.passes() - out.passes - partial;
    // Per pixel, with the passes it keeps without them (fewer where adaptive sampling stopped it).
    auto leaveOut = [&](int n) { return leavesOut(out, n, sampler); };
    const bool group = out.passes > 0 && out.sums && others > 0;
    if (partial > 0) {  // always out, with the others where they are
        if (film.tracksNoise())
            throw std::logic_error("finalImage: a film that tracks noise holds a pass of part of the image");
        if (!group || !leaveOut(others)) return film.rgbWithout(partial, *out.partialSums);
        std::vector<FixedSum> both = *out.sums;
        for (size_t i = 0; i < both.size() && i < out.partialSums->size(); ++i) both[i] += (*out.partialSums)[i];
        return film.rgbWithout(out.passes + partial, both);
    }
    if (!group) return film.rgb();
    if (!film.tracksNoise()) return leaveOut(others) ? film.rgbWithout(out.passes, *out.sums) : film.rgb();
    return film.rgbWithout(out.passes, *out.sums, leaveOut);
}

}  // namespace brume
