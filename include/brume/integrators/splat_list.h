// Contributions an integrator deposits at pixels other than its own sample's (light tracing,
// the t = 1 strategies of bidirectional path tracing), recorded in the order they are made.
// The film (film/film.h) merges them; to keep images independent of the thread count, each
// work unit (one tile of one pass) records into a list of its own, merged in tile order.
#pragma once
#include <cstdint>
#include <vector>

#include "brume/math/vec3.h"

namespace brume {

// Splats made by one work unit, in the order they were made. Reused from pass to pass
// (clear() keeps the capacity), so steady-state splatting does not allocate.
class SplatList {
public:
    struct Record {
        int x, y;
        Spectrum value;
    };
    // (fx, fy): film position in pixels, top-left origin, as Integrator::sample receives it.
    // Positions outside the image are ignored; non-finite values are dropped and counted.
    void splat(float fx, float fy, Spectrum value, int width, int height) {
        if (!(fx >= 0 && fy >= 0 && fx < float(width) && fy < float(height))) return;
        if (!isFinite(value)) {
            ++nonFinite_;
            return;
        }
        records_.push_back({int(fx), int(fy), value});
    }
    void clear() {
        records_.clear();
        nonFinite_ = 0;
    }
    const std::vector<Record>& records() const { return records_; }
    uint64_t nonFinite() const { return nonFinite_; }

private:
    std::vector<Record> records_;
    uint64_t nonFinite_ = 0;
};

}  // namespace brume
