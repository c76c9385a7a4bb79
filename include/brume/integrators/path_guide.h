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
    // Whether this pixel's walks record in the current pass.
    bool records(uint32_t pixel, int width, int height) const;
    // Hands in one walk's records (thread-safe: each thread has its own list).
    void add(const GuideRecord* records, int count) const;
    // The pixel's value as the training passes saw it (channel mean, 3×3 box filtered), for
    // guided survival once training is over (during training the throughput roulette keeps
    // every walk that sees light for the records: guided survival there cut the records of
    // a single-scattering scene to a few); −1 before, or for an image of another size.
    float pixelEstimate(uint32_t pixel, int width, int height) const {
        if (training() || width != estimateWidth_ || height != estimateHeight_ || pixelEstimate_.empty()) return -1.0f;
        return pixelEstimate_[pixel];
    }

    void endPass(const PassSummary& summary);
    std::string saveState() const;
    void loadState(const std::string& state);  // throws std::runtime_error for foreign bytes
    GuidingReport report() const;

private:
    struct Arena {
        std::vector<GuideRecord> records;
    };
    Arena& arena() const;
    bool training() const { return passes_ < kLastFitPass && records_.size() < kMaxRecords; }

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
    GuidingField field_;
    mutable std::mutex mutex_;
    mutable std::vector<std::unique_ptr<Arena>> arenas_;
};

}  // namespace brume
