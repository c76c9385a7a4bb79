// How much the bidirectional tracer trusts light tracing for single-scattered light: a
// variance-aware MIS factor (Grittmann, Georgiev, Slusallek, Křivánek 2019), learned from
// the render's own first passes.
//
// Why. A path camera → x1 → light (one scattering event) is made by the camera side (the
// light connection, free-flight and equi-angular, and the emitter hit) and by light tracing
// (the camera connection t = 1, free-flight and equi-angular towards the pinhole). Both
// families sample x1 nearly in proportion to the integrand (1/r² at both ends), so the power
// heuristic splits such paths by density, about evenly. But their errors differ: the camera
// side is stratified per pixel (Sobol), light tracing lands at random pixels. On four fogs
// nobody tuned on, single scattering, the plain weights gave 3.5–27× the error of the same
// samples with light tracing's densities counted 1/100 (docs/results.md).
//
// The factor. Variance-aware MIS weighs technique k by c_k·p_k with c_k = 1/v_k, v_k the
// variance of k used alone. Here two families: c = V_camera / V_light for the camera
// connection's densities on paths of one scattering event (MisSettings::directLightTracing;
// longer paths keep 1, where light tracing is what finds caustics and lights behind
// occluders). V comes from the first kPasses passes, which still render with c = 1: each
// contribution to a one-event path is also weighted as if its family were alone, and the two
// "alone" images are kept per pass. Consecutive passes (0, 1) and (2, 3) are aligned pairs of
// the pixel's sequence, so E[(a − b)²]/2 is the variance of a pass (the duel's argument,
// allocation_duel.h: exact for independent numbers, within 1.75× for a scrambled net), per
// pixel and channel in relative terms (weight 1/(Ī² + ε), Ī the pair's mean of both
// families). A median over kGroups interleaved pixel groups keeps one firefly from deciding.
//
// Limits. c stays within [kFloor, 1]. Never above 1: light tracing measured better than the
// camera side in four passes may be a light tracing that has not yet met its rare splats.
// Not below kFloor = 1/64: with 1e-4 the fog room (val_fog_room, single scattering) lost
// the paths where light tracing's density is 10⁴× the camera side's, a heavy tail that four
// passes rarely show (relative MSE 9.2e-6 at 1/100, 5.0e-5 at 1e-4, one seed of two).
//
// The learning passes render with c = 1, as many times noisier there as c gains (4 of 64
// passes held half the error of a 64-spp render of the thin lamp). So they are kept apart,
// as exact sums, and the image leaves them out once the others far outnumber them
// (Integrator::leftOut, render/renderer.h finalImage).
//
// Sobol numbers (the one-event split only, one_event_split.h). Independent passes cannot show
// what Sobol numbers give each family: the camera side, stratified per pixel, converges far
// faster than light tracing, which lands at random pixels. So after the learning passes the
// split's first kCheckPasses Sobol passes (rendered with κ as learned, and kept in the image)
// gather both families' alone images again, and the spread of their batches of 1 and 4 passes
// (allocation_duel.h) gives each family's gain over independent numbers at 4 passes,
//   G = V(1) / (4·V(4)),
// and κ ← κ·G_light / G_camera, within [kFloor, 1], from the pass after. (Measured at fixed
// spp, κ scaled after learning: 0.06× was best in dense fog beside a far light, where light
// tracing then lost 27× against the path tracer, 0.25× in the forward fog, 1× beside the thin
// lamp; docs/results.md.)
//
// Whether light tracing pays at all (the one-event split only). The check's passes also gather
// the split's own estimate of one-event paths (the camera side weighted W_C plus light
// tracing's weighted splats, with κ as learned), while the film takes the camera side alone
// (W_C = 1, light tracing's splats measured but not splatted: every check pass is then a
// path-tracer pass, unbiased). The spread of their batches of 2 and 4 passes gives each its
// variance at 4 passes and its rate α = log2(V(2)/V(4)) (within [1, 3]); carried to the
// render's N passes (--spp; 256 where not known), if the split's estimate beats the camera
// side alone by less than what light tracing and the weights cost,
//   V_alone(4)/V_split(4) · (N/4)^(α_split − α_alone) < (C_camera + C_light + kWeightCall·calls) / C_camera
// (counted from the check's passes, sample_cost.h's units; light tracing's splats are all
// traced there, so C_light is an upper bound), light tracing is turned off: κ = 0, q = 0, the
// split is the path tracer. (Measured at fixed spp after film positions by inverse distance,
// docs/results.md: on six fogs of point lights light tracing lowered no error by more than
// 1 %, raised it up to 2× in dense fog beside a far light, and cost 17–58 % more time per
// sample than the path tracer. Beside narrow spots it is far better at 4 passes, 14–80×, but
// the camera side's rate there is twice its own, hence the extrapolation.) Off is safe where
// the split applies: its camera side has no heavy tail there (equi-angular placement cancels
// the light's 1/r², the film positions the 1/D of a light in view, everything else is
// bounded), so there are no rare paths for light tracing to save.
//
// Deterministic: the camera-side image is written by each pixel's own sample; light
// tracing's lands anywhere and is summed in 64-bit fixed point (order-free); the factor is
// set at a pass boundary. Saved in checkpoints.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "brume/integrators/allocation_duel.h"
#include "brume/integrators/integrator.h"
#include "brume/integrators/state_bytes.h"
#include "brume/math/vec3.h"

namespace brume {

class DirectLightTracing {
public:
    static constexpr int kPasses = 4;      // learning passes: two aligned pairs
    static constexpr int kGroups = 9;      // pixel groups of the median
    static constexpr double kFloor = 1.0 / 64.0;
    static constexpr int kCheckPasses = AllocationDuel::kPasses;  // Sobol passes of the check

    // Whether pass `pass` gathers the alone images (call with the pass before it runs).
    bool learning(int pass) const { return pass < kPasses && passes_ == pass; }
    // Whether pass `pass` (counted as for learning) gathers the alone images of the check with
    // Sobol numbers (call with the pass before it runs; the one-event split only).
    bool checking(int pass) const {
        return passes_ == kPasses && pass >= kPasses && pass - kPasses == checkPasses_ && checkPasses_ < kCheckPasses;
    }
    // After a checking pass that completed (its counters, null: cost not counted): its images
    // into the batches; after the last, κ corrected or light tracing turned off, judged at
    // `renderPasses` passes (0: not known, kAssumedPasses).
    void endCheckPass(const PathCounts* counts = nullptr, int renderPasses = 0);
    static constexpr int kAssumedPasses = 256;
    // The factor in force (1 while learning, 0 when turned off).
    double factor() const { return off_ ? 0.0 : factor_; }
    // Whether the check turned light tracing off, and what it measured: V_alone / V_split and
    // the cost ratio it had to beat (0 until checked).
    bool off() const { return off_; }
    double splitGain() const { return splitGain_; }
    double costRatio() const { return costRatio_; }
    // The cost of one weight W_C beside the camera side's connection (sample_cost.h's units):
    // an estimate from one profile of the forward fog (val_forward, single scattering), where
    // the weights took about 12 % of the path tracer's time at 1.5 calls per sample; not fitted,
    // and not checked on other scenes.
    static constexpr double kWeightCall = 0.6;
    // The check's gains G_camera and G_light (0 until checked).
    double cameraGain() const { return gain_[0]; }
    double lightGain() const { return gain_[1]; }
    // How often a sample traces a light subpath where those serve only light tracing (single
    // scattering): as often as light tracing's share, q = max(c, kLeastShare). A technique made
    // q times per sample has q times its density in the weights and 1/q times its variance
    // per sample, so variance-aware MIS counts it q·c. Made less often, it costs less: its
    // subpath, two camera connections and their weights were about two thirds of a sample.
    // Not below kLeastShare = 1/16, so that q·c ≥ 1/1024 keeps the heavy tails light tracing
    // covers (see kFloor).
    double subpathShare() const { return off_ ? 0.0 : std::max(kLeastShare, factor_); }
    static constexpr double kLeastShare = 1.0 / 16.0;
    // V_camera and V_light as measured (0 until learned).
    double cameraVariance() const { return variance_[0]; }
    double lightVariance() const { return variance_[1]; }

    // The images of a width × height render, made by the first sample that needs them (any
    // thread; they are cleared after each learning pass).
    void ensureImages(int width, int height);
    // The camera side's alone estimate of one-event paths for pixel (x, y): one call per
    // sample, from that pixel's own sample.
    void addCamera(int x, int y, const Spectrum& v);
    // Light tracing's alone estimate landing in pixel (x, y) (any thread).
    void addLight(int x, int y, const Spectrum& v);
    // The check's split estimate of one-event paths: the camera side's weighted value (one call
    // per sample, from the pixel's own sample) and light tracing's weighted splats (any thread).
    void addSplitCamera(int x, int y, const Spectrum& v);
    void addSplitLight(int x, int y, const Spectrum& v);
    // After the learning pass completed: its images into the pair statistics; after the last,
    // the factor.
    void endPass(const PassSummary& summary);
    // After a learning pass that was abandoned: its images are thrown away.
    void discardPass();

    // The learning passes' exact sums as the film added them (3 per pixel), and how many.
    const std::vector<FixedSum>& passSums() const { return passSums_; }
    int passes() const { return passes_; }

    void save(std::string& out) const;
    void load(StateReader& reader);  // std::runtime_error if malformed

private:
    std::mutex mutex_;
    std::atomic<bool> ready_{false};
    int width_ = 0, height_ = 0;
    int passes_ = 0;  // learning passes completed
    int checkPasses_ = 0;  // checking passes completed
    AllocationDuel batches_[3];  // the check's batches: camera side, light tracing, the split (contender 0 each)
    std::vector<float> weights_;  // the check's pixel weights, 1/(Ī² + 0.01) from the learning passes
    double gain_[2] = {0, 0};
    double factor_ = 1.0;
    double variance_[2] = {0, 0};
    bool off_ = false;
    double splitGain_ = 0, costRatio_ = 0;
    double costs_[3] = {0, 0, 0};  // the check's counted cost: camera side, light tracing, weights
    std::vector<float> camera_;                       // this pass, 3 per pixel
    std::unique_ptr<std::atomic<int64_t>[]> light_;   // this pass, fixed point, 3 per pixel
    std::vector<float> splitCamera_;                      // the check's pass: W_C-weighted camera side
    std::unique_ptr<std::atomic<int64_t>[]> splitLight_;  // and light tracing's weighted splats
    std::vector<float> first_[2];                     // the pair's first pass, both families
    double squares_[2][kGroups] = {};                 // Σ w·(a − b)²/2 per family and pixel group
    std::vector<FixedSum> passSums_;
};

}  // namespace brume
