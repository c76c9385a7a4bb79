#include "brume/guiding/guiding_field.h"

#include <algorithm>
#include <atomic>
#include <limits>
#include <stdexcept>
#include <thread>

#include "brume/guiding/vmf_fit.h"
#include "brume/sampling/hg.h"

namespace brume {

namespace {

constexpr int kMaxDepth = 40;
constexpr size_t kDirectOnlySplit = 4;  // (chosen, not tuned: guided distances only)
// The shares α a cell may choose; at most 1/2, so phase sampling always keeps half and a
// poor fit costs at most a factor 2 in density (defensive mixture).
constexpr float kShares[] = {0.0f, 0.25f, 0.5f};
constexpr int kShareCount = int(sizeof kShares / sizeof kShares[0]);
constexpr double kGuidingCost = 0.1;

struct Range {
    size_t begin, end;
};

// One kind of vertex (medium or surface) of a leaf: its mixture and share, from the leaf's
// records of that kind. False if it should not guide.
// The mixture is fitted to every other record of the kind and the share chosen on the
// rest: on the records it was fitted to, a mixture predicts a lower second moment than it
// gives (seen: shares chosen that way raised the variance of a fog room by 5 %).
bool fitKind(const GuideRecord* r, size_t n, bool surface, const GuidingSettings& s, VmfMixture* mixture,
             float* share, float* adjoint, float* inscatter = nullptr, float* inscatter2 = nullptr) {
    std::vector<WeightedDirection> samples;
    std::vector<const GuideRecord*> heldOut;
    samples.reserve(n / 2 + 1);
    heldOut.reserve(n / 2 + 1);
    double walks = 0, brought = 0;  // the adjoint: Σ count · f L / p over Σ count
    double gathered = 0, gathered2 = 0;  // Σ count · X and Σ count · X², X = direct + f L / p
    for (size_t j = 0; j < n; ++j) {
        if (bool(r[j].surface) != surface || !(r[j].pdf > 0)) continue;
        walks += r[j].count;
        const double continued = double(r[j].scatter) * r[j].radiance / r[j].pdf, x = continued + r[j].direct;
        brought += r[j].count * continued;
        gathered += r[j].count * x;
        gathered2 += r[j].count * x * x;
    }
    if (walks >= s.minRecords) {
        *adjoint = float(brought / walks);
        if (inscatter) {
            *inscatter = float(gathered / walks);
            *inscatter2 = float(gathered2 / walks);
        }
    }
    for (size_t j = 0; j < n; ++j)
        if (bool(r[j].surface) == surface && r[j].radiance > 0 && r[j].pdf > 0) {
            if ((samples.size() + heldOut.size()) % 2 == 0) samples.push_back({r[j].wi, r[j].radiance / r[j].pdf});
            else heldOut.push_back(&r[j]);
        }
    if (samples.size() + heldOut.size() < size_t(s.minRecords)) return false;
    if (!fitVmfMixture(samples.data(), samples.size(), s.lobes, s.iterations, mixture)) return false;
    if (s.fixedShare >= 0) {
        *share = std::min(s.fixedShare, 1.0f);
        return *share > 0;
    }
    // M(α) = Σ_j (f_j L_j)² / (p_α,j · p_j) (guiding_field.h).
    double moment[kShareCount] = {};
    for (const GuideRecord* q : heldOut) {
        float pGuide;
        if (!surface) {
            VmfMixture product;
            pGuide = vmfProduct(*mixture, hgAsVmf(q->wIn, q->g), &product) ? product.pdf(q->wi) : 0.0f;
        } else {
            pGuide = mixture->pdf(q->wi);
        }
        const double f = double(q->scatter) * q->radiance;
        for (int k = 0; k < kShareCount; ++k) {
            const double pAlpha = kShares[k] * double(pGuide) + (1.0 - kShares[k]) * q->unguided;
            moment[k] += pAlpha > 0 ? f * f / (pAlpha * q->pdf) : 0.0;
        }
    }
    // A guided vertex costs more than an unguided one (a product of lobes, and the
    // mixture's density again for every light connection near it): a share must lower the
    // second moment by kGuidingCost to be taken.
    int best = 0;
    for (int k = 1; k < kShareCount; ++k)
        if (moment[k] < moment[best] && moment[k] < (1.0 - kGuidingCost) * moment[0]) best = k;
    *share = kShares[best];
    return *share > 0;
}

// A leaf's cell from its records, or false if it has too few of either kind.
bool fitCell(const GuideRecord* r, size_t n, const GuidingSettings& s, GuidingCell* cell) {
    const bool medium =
        fitKind(r, n, false, s, &cell->medium, &cell->share, &cell->mediumAdjoint, &cell->inscatter, &cell->inscatter2);
    const bool surface = fitKind(r, n, true, s, &cell->surface, &cell->surfaceShare, &cell->surfaceAdjoint);
    if (!medium) cell->share = 0;
    if (!surface) cell->surfaceShare = 0;
    return cell->mediumAdjoint >= 0 || cell->surfaceAdjoint >= 0;
}

}  // namespace

void GuidingField::build(std::vector<GuideRecord>& records, const GuidingSettings& settings) {
    nodes_.clear();
    cells_.clear();
    if (records.empty()) return;
    lo_ = hi_ = records[0].p;
    for (const GuideRecord& r : records) {
        lo_ = vmin(lo_, r.p);
        hi_ = vmax(hi_, r.p);
    }
    const Vec3 pad = (hi_ - lo_) * 1e-3f + Vec3(1e-4f);
    lo_ = lo_ - pad;
    hi_ = hi_ + pad;

    // Split top-down; leaves are listed in the order they are made.
    struct Task {
        uint32_t node;
        Range range;
        Vec3 lo, hi;
        int depth;
    };
    std::vector<Task> stack{{0, {0, records.size()}, lo_, hi_, 0}};
    std::vector<std::pair<uint32_t, Range>> leaves;
    nodes_.push_back(Node{});
    while (!stack.empty()) {
        const Task t = stack.back();
        stack.pop_back();
        // Only records that saw light count towards a split: those that saw it along their
        // direction carry the directions; those that saw it only by next-event estimation
        // carry the cell's in-scattered radiance (guided distances, which a scalar needs
        // fewer records for), and split a leaf at kDirectOnlySplit times as many; the dark
        // ones (kept one in 8) only lower the cell's means.
        size_t lit = 0, directOnly = 0;
        for (size_t i = t.range.begin; i < t.range.end; ++i) {
            lit += records[i].radiance > 0;
            directOnly += settings.inscatter && !(records[i].radiance > 0) && records[i].direct > 0;
        }
        if ((lit <= size_t(settings.maxRecords) && directOnly <= kDirectOnlySplit * size_t(settings.maxRecords)) ||
            t.depth >= kMaxDepth) {
            leaves.push_back({t.node, t.range});
            continue;
        }
        const Vec3 size = t.hi - t.lo;
        const int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
        const float split = 0.5f * (t.lo[axis] + t.hi[axis]);
        auto mid = std::stable_partition(records.begin() + long(t.range.begin), records.begin() + long(t.range.end),
                                         [&](const GuideRecord& r) { return r.p[axis] < split; });
        const size_t m = size_t(mid - records.begin());
        const uint32_t left = uint32_t(nodes_.size());
        nodes_[t.node] = Node{split, uint32_t(axis), left};
        nodes_.push_back(Node{});
        nodes_.push_back(Node{});
        Vec3 leftHi = t.hi, rightLo = t.lo;
        leftHi[axis] = split;
        rightLo[axis] = split;
        stack.push_back({left + 1, {m, t.range.end}, rightLo, t.hi, t.depth + 1});
        stack.push_back({left, {t.range.begin, m}, t.lo, leftHi, t.depth + 1});
    }

    // Leaves are fitted independently, in parallel; the result does not depend on who fits which.
    std::vector<GuidingCell> fitted(leaves.size());
    std::vector<char> guides(leaves.size(), 0);
    std::atomic<size_t> next{0};
    auto worker = [&] {
        for (size_t i = next++; i < leaves.size(); i = next++) {
            const Range r = leaves[i].second;
            guides[i] = fitCell(records.data() + r.begin, r.end - r.begin, settings, &fitted[i]);
        }
    };
    const unsigned threads = settings.threads > 0 ? unsigned(settings.threads) : std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (unsigned i = 1; i < std::min<size_t>(threads, leaves.size()); ++i) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    for (size_t i = 0; i < leaves.size(); ++i) {
        Node& n = nodes_[leaves[i].first];
        n.axis = 3;
        n.index = kNoCell;
        if (guides[i]) {
            n.index = uint32_t(cells_.size());
            cells_.push_back(fitted[i]);
        }
    }
}

const GuidingCell* GuidingField::lookup(Vec3 p) const {
    if (nodes_.empty()) return nullptr;
    if (!(p.x >= lo_.x && p.y >= lo_.y && p.z >= lo_.z && p.x <= hi_.x && p.y <= hi_.y && p.z <= hi_.z)) return nullptr;
    uint32_t i = 0;
    for (;;) {
        const Node& n = nodes_[i];
        if (n.axis == 3) return n.index == kNoCell ? nullptr : &cells_[n.index];
        i = n.index + (p[int(n.axis)] >= n.split ? 1u : 0u);
    }
}

int GuidingField::along(Vec3 o, Vec3 d, float tMax, Interval* out, int maxCount) const {
    if (nodes_.empty()) return 0;
    // The ray clipped to the tree's box (slabs), then a front-to-back walk down the tree:
    // at an inner node the part of [t0, t1] on the origin's side of the plane comes first.
    float t0 = 0, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0) {
            if (o[a] < lo_[a] || o[a] > hi_[a]) return 0;
            continue;
        }
        const float inv = 1.0f / d[a];
        float tn = (lo_[a] - o[a]) * inv, tf = (hi_[a] - o[a]) * inv;
        if (tn > tf) std::swap(tn, tf);
        t0 = std::max(t0, tn);
        t1 = std::min(t1, tf);
    }
    if (!(t0 < t1)) return 0;
    struct Todo {
        uint32_t node;
        float t0, t1;
    };
    Todo stack[kMaxDepth + 2];
    int top = 0, count = 0;
    stack[top++] = {0, t0, t1};
    while (top > 0) {
        Todo t = stack[--top];
        for (;;) {
            const Node& n = nodes_[t.node];
            if (n.axis == 3) {
                if (count == maxCount) return -1;
                out[count++] = Interval{t.t0, t.t1, n.index == kNoCell ? nullptr : &cells_[n.index]};
                break;
            }
            const int a = int(n.axis);
            // lookup's rule: a point on the plane belongs to the right child.
            const bool leftFirst = o[a] < n.split || (o[a] == n.split && d[a] < 0);
            const uint32_t first = n.index + (leftFirst ? 0u : 1u), second = n.index + (leftFirst ? 1u : 0u);
            const float tSplit = d[a] != 0 ? (n.split - o[a]) / d[a] : std::numeric_limits<float>::infinity();
            if (tSplit <= 0 || tSplit >= t.t1) {  // the plane behind the origin or past the piece
                t.node = first;
            } else if (tSplit <= t.t0) {  // crossed before the piece
                t.node = second;
            } else {
                stack[top++] = {second, tSplit, t.t1};
                t = {first, t.t0, tSplit};
            }
        }
    }
    return count;
}

size_t GuidingField::guidingCells() const {
    size_t n = 0;
    for (const GuidingCell& c : cells_) n += c.share > 0 || c.surfaceShare > 0;
    return n;
}

size_t GuidingField::leaves() const {
    size_t n = 0;
    for (const Node& node : nodes_) n += node.axis == 3;
    return n;
}

void GuidingField::assign(Vec3 lo, Vec3 hi, std::vector<Node> nodes, std::vector<GuidingCell> cells) {
    // Every inner node's children come after it and inside the list; every leaf's cell exists.
    for (size_t i = 0; i < nodes.size(); ++i) {
        const Node& n = nodes[i];
        const bool ok = n.axis == 3 ? (n.index == kNoCell || n.index < cells.size())
                                    : (n.axis < 3 && n.index > i && size_t(n.index) + 1 < nodes.size());
        if (!ok) throw std::runtime_error("guiding state is malformed");
    }
    for (const GuidingCell& c : cells)
        for (const VmfMixture* m : {&c.medium, &c.surface})
            if (m->count < 0 || m->count > VmfMixture::kMaxLobes) throw std::runtime_error("guiding state is malformed");
    lo_ = lo;
    hi_ = hi;
    nodes_ = std::move(nodes);
    cells_ = std::move(cells);
}

}  // namespace brume
