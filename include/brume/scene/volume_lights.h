// Emissive media as lights: next-event estimation towards a glowing grid (fire, glowing
// smoke) draws a point y in proportion to an upper bound of the power the media emit: a
// medium, then one of its emission grid's stored bricks, each in proportion to
//     world volume × mean(|e(majorant)|)
// (e at the majorant, the largest value in the brick: e grows with the grid's value, linearly
// or as a blackbody's, whose cool channels may be negative; every point that emits can be
// drawn), then y
// uniform in the brick. Its volume density is p(y) = P(medium)·P(brick)/V_brick; the caller
// weighs e(y) by it. Only media with an emission grid are sampled: constant emission has no
// bounded region to draw from (it stays with the camera walk's gathering, medium_emission.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include "brume/math/mat4.h"
#include "brume/sampling/distribution1d.h"
#include "brume/scene/medium.h"

namespace brume {

struct VolumeLightSample {
    Vec3 p;          // world point
    int medium = -1; // the medium it is in, if its bounding mesh holds it (the caller checks)
    size_t brick = 0;  // its brick in the medium's emission grid (DensityGrid::brickAt)
    float pdf = 0;   // volume density of p, 1/m³
};

class VolumeLights {
public:
    VolumeLights() = default;
    explicit VolumeLights(const std::vector<Medium>& media);
    bool empty() const { return media_.empty(); }
    // Whether next-event estimation samples this medium's emission (it has an emission grid).
    bool samples(int medium) const { return medium >= 0 && size_t(medium) < sampled_.size() && sampled_[size_t(medium)]; }
    // uPick chooses the medium and the brick (rescaled between the two); u3 the point in it.
    bool sample(float uPick, Vec3 u3, VolumeLightSample* s) const;
    // The volume density with which sample() draws a point in this brick of the medium's
    // emission grid (0 where it draws none).
    float pdf(int medium, size_t brick) const {
        const int g = samples(medium) ? gridOf_[size_t(medium)] : -1;
        return g >= 0 && brick < grids_[size_t(g)].pdf.size() ? grids_[size_t(g)].pdf[brick] : 0.0f;
    }
    size_t memoryBytes() const;

private:
    struct Grid {
        int medium = -1;
        Distribution1D bricks;      // over `slots`
        std::vector<uint32_t> slot; // the brick index (x fastest) of each entry
        std::vector<float> pdf;     // per brick of the grid: the volume density of its points
        Mat4 localToWorld;          // the emission grid's local voxel coordinates → world
        float brickVolume = 0;      // m³
        int bn[2] = {0, 0};         // bricks per axis (x, y)
    };
    std::vector<Grid> grids_;
    Distribution1D media_;  // over grids_
    std::vector<bool> sampled_;
    std::vector<int> gridOf_;  // per medium: its entry in grids_, or −1
};

}  // namespace brume
