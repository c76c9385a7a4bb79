// --stats: each technique's share of the image and of its noise. Per technique, the sum over
// samples of its weighted contribution to one pixel (the mean of the channels), and the sum of
// the squares of those per-sample, per-pixel totals (Σ over a sample's depths first: a
// technique's estimate of a pixel is its whole contribution to it). A technique with a small
// share of the image and a large share of the squares is where the noise comes from.
// Summed per tile and added in tile order, like the other PathStats.
#pragma once
#include "brume/math/vec3.h"

namespace brume {

struct TechniqueSums {
    // The bidirectional tracer: 2·kind + [equi-angular variant] (path_stats.h, techniqueSlot);
    // the path tracer: 8 + PathTracerTechnique (auto may render with either).
    static constexpr int kSlots = 12;
    double sum[kSlots] = {}, squares[kSlots] = {};

    void add(const TechniqueSums& o) {
        for (int k = 0; k < kSlots; ++k) sum[k] += o.sum[k], squares[k] += o.squares[k];
    }
    // A contribution that is a pixel's whole share of one sample (a splat of light tracing).
    void addAlone(int slot, const Spectrum& v) {
        const double g = grey(v);
        sum[slot] += g;
        squares[slot] += g * g;
    }
    static double grey(const Spectrum& v) { return (double(v.x) + double(v.y) + double(v.z)) / 3.0; }
};

enum class PathTracerTechnique : int { EmitterHit, AtVertex, OnSegment, BySolidAngle };
constexpr int techniqueSlot(PathTracerTechnique t) { return 8 + int(t); }

// One sample's contributions to its own pixel, per technique, until the sample is done.
struct TechniqueSample {
    double value[TechniqueSums::kSlots] = {};
    void add(int slot, const Spectrum& v) { value[slot] += TechniqueSums::grey(v); }
    void addTo(TechniqueSums& s) const {
        for (int k = 0; k < TechniqueSums::kSlots; ++k) s.sum[k] += value[k], s.squares[k] += value[k] * value[k];
    }
};

}  // namespace brume
