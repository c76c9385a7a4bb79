#include "brume/integrators/path_guide.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "brume/integrators/state_bytes.h"

namespace brume {

namespace {

std::atomic<uint64_t> nextId{1};
constexpr uint32_t kMagic = 0x47445031;  // "GDP1"

struct ArenaCache {
    uint64_t owner = 0;
    void* arena = nullptr;
};
thread_local ArenaCache cache;

}  // namespace

PathGuide::PathGuide(GuidingSettings settings) : id_(nextId++), settings_(settings) {
    if (const char* e = std::getenv("BRUME_GUIDE_SHARE")) settings_.fixedShare = float(std::atof(e));  // TEMP
    if (const char* e = std::getenv("BRUME_GUIDE_LEAF")) settings_.maxRecords = std::atoi(e);  // TEMP
    if (const char* e = std::getenv("BRUME_GUIDE_LOBES")) settings_.lobes = std::atoi(e);  // TEMP
}

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
    if (!summary.complete || !training()) return;
    ++passes_;
    std::sort(pass.begin(), pass.end(), [](const GuideRecord& a, const GuideRecord& b) {
        return a.pixel != b.pixel ? a.pixel < b.pixel : a.vertex < b.vertex;
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
    ++fits_;
    if (std::getenv("BRUME_DEBUG_GUIDE")) {  // TEMP
        int hm[5] = {}, hs[5] = {};
        auto bin = [](float a) { return a <= 0 ? 0 : a <= 0.25f ? 1 : a <= 0.5f ? 2 : a <= 0.75f ? 3 : 4; };
        double kap = 0; int nl = 0;
        for (const GuidingCell& c : field_.cells()) {
            ++hm[bin(c.share)];
            ++hs[bin(c.surfaceShare)];
            for (int i = 0; i < c.medium.count; ++i) kap += c.medium.lobe[i].kappa * c.medium.weight[i];
            ++nl;
        }
        for (Vec3 q : {Vec3(2.99f, 1.4f, 0.0f), Vec3(0.0f, 0.01f, 1.0f), Vec3(-2.99f, 1.4f, 1.0f), Vec3(0.5f, 1.5f, 0.5f)}) {
            const GuidingCell* c = field_.lookup(q);
            if (!c) { std::fprintf(stderr, "  (%g %g %g): no cell\n", q.x, q.y, q.z); continue; }
            Vec3 door = normalize(Vec3(0.0f, 1.05f, -2.0f) - q);
            std::fprintf(stderr, "  (%g %g %g): %u records, share %.2f surf %.2f, pdf at door %.3f; lobes:", q.x, q.y, q.z, c->records, c->share, c->surfaceShare, c->surface.pdf(door));
            for (int i = 0; i < c->surface.count; ++i) std::fprintf(stderr, " [w %.2f k %.1f cos-to-door %.2f]", c->surface.weight[i], c->surface.lobe[i].kappa, dot(c->surface.lobe[i].mu, door));
            std::fprintf(stderr, "\n");
        }
        std::fprintf(stderr, "fit %d (%zu records, %zu leaves): medium shares %d %d %d %d %d, surface %d %d %d %d %d, mean kappa %.1f\n",
                     fits_, records_.size(), field_.leaves(), hm[0], hm[1], hm[2], hm[3], hm[4], hs[0], hs[1], hs[2], hs[3], hs[4], nl ? kap / nl : 0.0);
    }
    learnSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!training()) records_ = std::vector<GuideRecord>();  // frozen: the records are not needed again
}

std::string PathGuide::saveState() const {
    std::string out;
    putBytes(out, kMagic);
    putBytes(out, int32_t(passes_));
    putBytes(out, int32_t(fits_));
    putVector(out, records_);
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
