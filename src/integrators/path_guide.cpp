#include "brume/integrators/path_guide.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "brume/integrators/state_bytes.h"

namespace brume {

namespace {

std::atomic<uint64_t> nextId{1};
constexpr uint32_t kMagic = 0x47445035;  // "GDP5"

struct ArenaCache {
    uint64_t owner = 0;
    void* arena = nullptr;
};
thread_local ArenaCache cache;

}  // namespace

PathGuide::PathGuide(GuidingSettings settings) : id_(nextId++), settings_(settings) {}

PathGuide::Arena& PathGuide::arena() const {
    if (cache.owner != id_) {
        std::lock_guard<std::mutex> lock(mutex_);
        arenas_.push_back(std::make_unique<Arena>());
        cache = ArenaCache{id_, arenas_.back().get()};
    }
    return *static_cast<Arena*>(cache.arena);
}

bool PathGuide::records(uint32_t pixel, int width, int height) const {
    if (!training()) return false;
    const uint64_t pixels = uint64_t(width) * uint64_t(height);
    const uint64_t stride = (pixels + kRecordPixels - 1) / kRecordPixels;
    return stride <= 1 || (uint64_t(pixel) * 2654435761u >> 7) % stride == 0;
}

void PathGuide::add(const GuideRecord* records, int count) const {
    std::vector<GuideRecord>& list = arena().records;
    list.insert(list.end(), records, records + count);
}

void PathGuide::endPass(const PassSummary& summary) {
    std::vector<GuideRecord> pass;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& a : arenas_) {
            if (summary.complete) pass.insert(pass.end(), a->records.begin(), a->records.end());
            a->records.clear();
        }
    }
    if (!summary.complete) return;
    if (!training()) return measureNoise(summary, false);
    ++passes_;
    if (summary.radiance) addPassExact(summary, trainingSums_);
    measureNoise(summary, true);
    if (summary.radiance) {
        const size_t n = size_t(summary.width) * size_t(summary.height);
        if (summary.width != estimateWidth_ || summary.height != estimateHeight_) {
            estimateWidth_ = summary.width;
            estimateHeight_ = summary.height;
            pixelSums_.assign(n, 0.0);
        }
        for (size_t i = 0; i < n; ++i) {
            const Spectrum& L = summary.radiance[i];
            pixelSums_[i] += (double(L.x) + L.y + L.z) / 3.0;
        }
    }
    // A total order, whatever order the threads handed the records in: (pixel, vertex), then
    // the record's bytes. (pixel, vertex) alone is not unique: a film position x + u with u
    // within a float's step of 1 rounds to the next pixel, whose own walk then shares its
    // keys, and an unstable sort of the two made the fits, and so the images, depend on the
    // thread count.
    std::sort(pass.begin(), pass.end(), [](const GuideRecord& a, const GuideRecord& b) {
        if (a.pixel != b.pixel) return a.pixel < b.pixel;
        if (a.vertex != b.vertex) return a.vertex < b.vertex;
        return std::memcmp(&a, &b, sizeof(GuideRecord)) < 0;
    });
    const size_t room = kMaxRecords - records_.size();
    records_.insert(records_.end(), pass.begin(), pass.begin() + long(std::min(room, pass.size())));
    const bool refit = (passes_ & (passes_ - 1)) == 0 || !training();  // 1, 2, 4, 8, 16, or full
    if (!refit) return;
    const auto start = std::chrono::steady_clock::now();
    // build() reorders its input: a copy, or every k-th record.
    std::vector<GuideRecord> ordered;
    const size_t stride = (records_.size() + kFitRecords - 1) / kFitRecords;
    ordered.reserve(records_.size() / std::max<size_t>(stride, 1) + 1);
    for (size_t i = 0; i < records_.size(); i += std::max<size_t>(stride, 1)) ordered.push_back(records_[i]);
    field_.build(ordered, settings_);
    // The pixel estimate: the mean of the training passes, 3×3 box filtered (one sample a
    // pass is noisy; guided survival needs its scale, not its detail).
    pixelEstimate_.assign(pixelSums_.size(), 0.0f);
    for (int y = 0; y < estimateHeight_; ++y)
        for (int x = 0; x < estimateWidth_; ++x) {
            double sum = 0;
            int n = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= estimateWidth_ || yy >= estimateHeight_) continue;
                    sum += pixelSums_[size_t(yy) * size_t(estimateWidth_) + size_t(xx)];
                    ++n;
                }
            pixelEstimate_[size_t(y) * size_t(estimateWidth_) + size_t(x)] = float(sum / (double(n) * passes_));
        }
    updateMeanEstimate();
    ++fits_;
    learnSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!training()) {  // frozen: the records are not needed again; the training pairs' noise
        records_ = std::vector<GuideRecord>();
        pairFirst_ = std::vector<float>();
        trainingNoise_ = 0;
        if (trainingPairs_.size() == pixelEstimate_.size())
            for (size_t i = 0; i < trainingPairs_.size(); ++i) trainingNoise_ += trainingPairs_[i] * noiseWeight(i);
        trainingPairs_ = std::vector<double>();
    }
}

// w_px = 1 / (I_px² + (Ī/10)²) (path_guide.h, leftOut).
double PathGuide::noiseWeight(size_t pixel) const {
    const double I = pixelEstimate_[pixel], floor = 0.1 * meanEstimate_;
    const double d = I * I + floor * floor;
    return d > 0 ? 1.0 / d : 0.0;
}

void PathGuide::updateMeanEstimate() {
    double sum = 0;
    for (float v : pixelEstimate_) sum += v;
    meanEstimate_ = pixelEstimate_.empty() ? 0.0 : sum / double(pixelEstimate_.size());
}

// Pairs of consecutive passes of one kind: the first pass's image is kept, the second's
// difference from it added (path_guide.h, leftOut).
void PathGuide::measureNoise(const PassSummary& summary, bool trainingPass) {
    if (!summary.radiance || (!trainingPass && guidedPasses_ >= 2 * kNoisePairs)) return;
    const size_t n = size_t(summary.width) * size_t(summary.height);
    if (!trainingPass && pixelEstimate_.size() != n) return;
    // The pass's image, channel means, with its splats (a bidirectional pass's light tracing).
    std::vector<float> image(n);
    for (size_t i = 0; i < n; ++i) image[i] = (summary.radiance[i].x + summary.radiance[i].y + summary.radiance[i].z) / 3.0f;
    for (int l = 0; l < summary.splatLists; ++l)
        for (const SplatList::Record& r : summary.splats[l].records())
            if (r.x >= 0 && r.y >= 0 && r.x < summary.width && r.y < summary.height)
                image[size_t(r.y) * size_t(summary.width) + size_t(r.x)] += (r.value.x + r.value.y + r.value.z) / 3.0f;
    if (!trainingPass) ++guidedPasses_;
    if (pairFirst_.size() != n) {
        pairFirst_ = std::move(image);
        return;
    }
    if (trainingPass) {
        if (trainingPairs_.size() != n) trainingPairs_.assign(n, 0.0);
        for (size_t i = 0; i < n; ++i) trainingPairs_[i] += double(image[i] - pairFirst_[i]) * double(image[i] - pairFirst_[i]);
        ++trainingPairCount_;
    } else {
        for (size_t i = 0; i < n; ++i) guidedNoise_ += double(image[i] - pairFirst_[i]) * double(image[i] - pairFirst_[i]) * noiseWeight(i);
    }
    pairFirst_ = std::vector<float>();
}

Integrator::LeftOutPasses PathGuide::leftOut() const {
    if (training() || passes_ <= 0 || trainingSums_.empty()) return {};
    double noise = 0;
    if (guidedPasses_ >= 2 * kNoisePairs && guidedNoise_ > 0 && trainingPairCount_ > 0)
        noise = (trainingNoise_ / trainingPairCount_) / (guidedNoise_ / kNoisePairs);
    return Integrator::LeftOutPasses{passes_, &trainingSums_, noise};
}

std::string PathGuide::saveState() const {
    std::string out;
    putBytes(out, kMagic);
    putBytes(out, int32_t(passes_));
    putBytes(out, int32_t(fits_));
    putVector(out, records_);
    putBytes(out, int32_t(estimateWidth_));
    putBytes(out, int32_t(estimateHeight_));
    putVector(out, pixelSums_);
    putVector(out, pixelEstimate_);
    putVector(out, trainingSums_);
    putVector(out, pairFirst_);
    putVector(out, trainingPairs_);
    putBytes(out, trainingNoise_);
    putBytes(out, guidedNoise_);
    putBytes(out, int32_t(trainingPairCount_));
    putBytes(out, int32_t(guidedPasses_));
    putBytes(out, field_.lower());
    putBytes(out, field_.upper());
    putVector(out, field_.nodes());
    putVector(out, field_.cells());
    return out;
}

void PathGuide::loadState(const std::string& state) {
    StateReader in{state};
    if (in.get<uint32_t>() != kMagic) throw std::runtime_error("guiding state is not this version's");
    passes_ = in.get<int32_t>();
    fits_ = in.get<int32_t>();
    records_ = in.getVector<GuideRecord>(kMaxRecords);
    estimateWidth_ = in.get<int32_t>();
    estimateHeight_ = in.get<int32_t>();
    pixelSums_ = in.getVector<double>(size_t(1) << 31);
    pixelEstimate_ = in.getVector<float>(size_t(1) << 31);
    trainingSums_ = in.getVector<FixedSum>(size_t(3) << 31);
    pairFirst_ = in.getVector<float>(size_t(1) << 31);
    trainingPairs_ = in.getVector<double>(size_t(1) << 31);
    trainingNoise_ = in.get<double>();
    guidedNoise_ = in.get<double>();
    trainingPairCount_ = in.get<int32_t>();
    guidedPasses_ = in.get<int32_t>();
    updateMeanEstimate();
    const size_t pixels = size_t(std::max(estimateWidth_, 0)) * size_t(std::max(estimateHeight_, 0));
    auto sized = [&](size_t size, size_t per) { return size == 0 || size == per * pixels; };
    if (pixelSums_.size() != pixels || !sized(pixelEstimate_.size(), 1) || !sized(trainingSums_.size(), 3) ||
        !sized(pairFirst_.size(), 1) || !sized(trainingPairs_.size(), 1) || trainingPairCount_ < 0 || guidedPasses_ < 0 ||
        !(trainingNoise_ >= 0) || !(guidedNoise_ >= 0))
        throw std::runtime_error("guiding state is malformed");
    const Vec3 lo = in.get<Vec3>(), hi = in.get<Vec3>();
    auto nodes = in.getVector<GuidingField::Node>(size_t(1) << 26);
    auto cells = in.getVector<GuidingCell>(size_t(1) << 26);
    if (passes_ < 0 || in.at != state.size()) throw std::runtime_error("guiding state is malformed");
    field_.assign(lo, hi, std::move(nodes), std::move(cells));
}

GuidingReport PathGuide::report() const {
    GuidingReport r;
    r.leaves = field_.leaves();
    r.cells = field_.guidingCells();
    r.records = records_.size();
    r.fieldBytes = field_.memoryBytes();
    r.recordBytes = records_.capacity() * sizeof(GuideRecord);
    r.fits = fits_;
    r.learnSeconds = learnSeconds_;
    return r;
}

std::string GuidingReport::text() const {
    char line[256];
    std::snprintf(line, sizeof line,
                  "guiding: %zu leaves, %zu guiding cells, %.2f MiB field + %.2f MiB records; %d fits, %.2f s learning\n",
                  leaves, cells, fieldBytes / 1048576.0, recordBytes / 1048576.0, fits, learnSeconds);
    return line;
}

}  // namespace brume
