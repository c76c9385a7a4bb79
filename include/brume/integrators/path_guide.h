// Learning a guiding field from the render's own passes (docs/path-guiding.md). Camera
// walks hand in their training records (guide_record.h) from any thread; at the end of each
// complete pass the records are put in a fixed order (pixel, then vertex), so the field is
// the same for any thread count. The field is rebuilt from every record so far after
// training passes 1, 2, 4, 8 and 16, then frozen: later passes only read it. Records are
// all importance samples of the incident radiance (weights L / p, whatever guide drew
// them), so the early ones stay valid for the later fits.
//
// Memory: at most kMaxRecords records (64 bytes each); on large images only every
// stride-th pixel (by a hash of its index) records, stride = ⌈pixels / kRecordPixels⌉.
// Time: a fit reads at most kFitRecords of them (every k-th, in their fixed order), so
// learning costs at most about five fits of that size.
#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "brume/guiding/guiding_field.h"
#include "brume/integrators/integrator.h"

namespace brume {

struct GuidingReport {
    size_t leaves = 0, cells = 0, records = 0, fieldBytes = 0, recordBytes = 0;
    int fits = 0;
    double learnSeconds = 0;  // fitting time (wall clock; not part of any result)
    std::string text() const;
};

class PathGuide {
public:
    static constexpr int kLastFitPass = 16;
    static constexpr size_t kMaxRecords = size_t(1) << 20;
    static constexpr size_t kFitRecords = size_t(1) << 17;
    static constexpr uint64_t kRecordPixels = 1 << 16;

    explicit PathGuide(GuidingSettings settings = {});

    // The field the current pass reads (null before the first fit).
    const GuidingField* field() const { return field_.empty() ? nullptr : &field_; }
    const GuidingSettings& settings() const { return settings_; }
    // Whether this pixel's walks record in the current pass.
    bool records(uint32_t pixel, int width, int height) const;
    // Hands in one walk's records (thread-safe: each thread has its own list).
    void add(const GuideRecord* records, int count) const;
    // The pixel's value as the training passes so far saw it (channel mean, 3×3 box
    // filtered), for guided survival; −1 before the first fit, or for an image of another
    // size. (During training the path tracer survives by the larger of this and the
    // throughput roulette, so no walk the records need is cut more often than before.)
    float pixelEstimate(uint32_t pixel, int width, int height) const {
        if (width != estimateWidth_ || height != estimateHeight_ || pixelEstimate_.empty()) return -1.0f;
        return pixelEstimate_[pixel];
    }
    bool training() const { return passes_ < kLastFitPass && records_.size() < kMaxRecords; }
    // Whether the next pass still teaches it: a training pass, or a guided pass whose noise
    // it measures (leftOut).
    bool learning() const { return training() || guidedPasses_ < 2 * kNoisePairs; }
    // Complete training passes so far (kLastFitPass, or fewer if the records filled up).
    int trainingPasses() const { return passes_; }

    // The training passes, which the image may leave out (Integrator::leftOut, renderer.h
    // finalImage): their walks are unguided or guided by early fits and end by the
    // throughput roulette, so once the guided passes outnumber them they mostly add noise.
    // Their noise per pass over the guided passes' is measured on pairs of consecutive
    // passes (training passes 1–16, guided passes 17–32):
    //   noise = mean_pairs Σ_px (L_a − L_b)² w_px  over the same for the guided pairs,
    //   w_px = 1 / (I_px² + (Ī/10)²)
    // with I the frozen pixel estimate (relative errors, as the image's relative MSE weighs
    // them); 0 until 8 guided pairs are seen.
    Integrator::LeftOutPasses leftOut() const;

    void endPass(const PassSummary& summary);
    std::string saveState() const;
    void loadState(const std::string& state);  // throws std::runtime_error for foreign bytes
    GuidingReport report() const;

private:
    struct Arena {
        std::vector<GuideRecord> records;
    };
    Arena& arena() const;
    void measureNoise(const PassSummary& summary, bool trainingPass);
    double noiseWeight(size_t pixel) const;
    void updateMeanEstimate();
    static constexpr int kNoisePairs = 8;

    uint64_t id_;
    GuidingSettings settings_;
    int passes_ = 0;  // complete passes seen
    int fits_ = 0;
    double learnSeconds_ = 0;
    std::vector<GuideRecord> records_;  // every record so far (until frozen)
    // The training passes' images, summed (channel means), and their filtered mean.
    int estimateWidth_ = 0, estimateHeight_ = 0;
    std::vector<double> pixelSums_;
    std::vector<float> pixelEstimate_;
    // leftOut: the training passes' exact sums; the pair noise measure (previous pass's
    // channel means, the training pairs' squared differences per pixel, weighted sums).
    std::vector<FixedSum> trainingSums_;
    std::vector<float> pairFirst_;
    std::vector<double> trainingPairs_;
    double trainingNoise_ = 0, guidedNoise_ = 0;
    int trainingPairCount_ = 0, guidedPasses_ = 0;
    double meanEstimate_ = 0;  // Ī, the pixel estimate's mean (with it)
    GuidingField field_;
    mutable std::mutex mutex_;
    mutable std::vector<std::unique_ptr<Arena>> arenas_;
};

}  // namespace brume
