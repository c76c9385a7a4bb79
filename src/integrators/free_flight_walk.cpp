#include "brume/integrators/free_flight_walk.h"

#include "brume/integrators/volume_light_sampling.h"

namespace brume {

namespace {

// FlightEmission's channel weight for a piece reached with pass densities `pass` so far.
float channelWeight(const FlightEmission& e, const Channels& pass) {
    if (e.channels == 1) return 1.0f;
    const double hero = e.prefix[e.hero] * pass[e.hero];
    if (!(hero > 0)) return 0.0f;
    double sum = 0;
    for (int c = 0; c < 3; ++c) sum += misPower(e.heuristic, e.prefix[c] * pass[c] / hero);
    return float(double(e.channels) / sum);
}

}  // namespace

Flight sampleFlight(const Scene& scene, const WalkSegment& seg, const MediumStack& media, bool startIsPoint,
                    Spectrum channels, Spectrum tracking, const Sampler& sampler, uint32_t dims, PathStats& stats,
                    bool passThrough, FlightEmission* emission, std::vector<FlightCrossing>* crossings) {
    Flight f;
    const Ray ray{seg.o, seg.d, seg.end};
    BoundaryWalk walk(scene, seg, media, stats);
    BoundaryPiece piece;
    while (walk.next(&piece)) {
        if (piece.index == 0) f.firstEnd = piece.t1;
        if (emission && piece.medium && piece.medium->emissive()) {  // before the piece's flight
            const float u = sampler.get1D(emission->dims + dim::kEmission, uint32_t(piece.index));
            const int mi = scene.mediumIndex(piece.medium);
            const Medium::PointWeight weight = gatheringWeight(scene, mi, emission->dirPdf);
            const bool weighted = emission->againstVolumeLights && scene.volumeLights().samples(mi);
            const Spectrum e = piece.medium->emitted(ray, piece.t0, piece.t1, u, weighted ? &weight : nullptr);
            if (!isBlack(e)) emission->gathered += f.weight * e * channelWeight(*emission, f.fwd);
        }
        if (piece.medium && passThrough) {
            // Passed for certain: weight T, forward density 1; the reverse walk's as usual.
            MediumTransit tr = piece.medium->transit(ray, piece.t0, piece.t1, startIsPoint && piece.index == 0, false);
            f.weight *= tr.T;
            f.rev *= tr.rev;
            if (isBlack(tr.T)) break;  // an unbounded ray through a medium
        } else if (piece.medium) {
            const uint32_t repeat = uint32_t(piece.index);
            const Medium& m = *piece.medium;
            const float uChannel = m.grey() ? 0.0f : sampler.get1D(dims + dim::kChannel, repeat);
            MediumSample ms = m.sampleDistance(ray, piece.t0, piece.t1, sampler.get1D(dims + dim::kDistance, repeat),
                                               uChannel, m.heterogeneous() ? tracking : channels,
                                               startIsPoint && piece.index == 0);
            f.weight *= ms.weight;
            f.fwd *= ms.fwd;
            f.rev *= ms.rev;
            if (ms.scattered) {
                f.end = Flight::End::Collision;
                f.t = ms.t;
                f.medium = piece.medium;
                break;
            }
            if (isBlack(ms.weight)) break;  // flew to infinity through a medium
        }
        if (crossings && piece.boundary && scene.transparentEmitter(piece.hit))
            crossings->push_back(FlightCrossing{piece.t1, piece.hit, f.weight, f.fwd, f.rev, piece.index > 0});
        if (piece.hit.valid() && !piece.boundary) {
            f.end = Flight::End::Surface;
            f.t = piece.t1;
            f.hit = piece.hit;
            break;
        }
    }
    f.media = walk.media();
    f.crossed = walk.crossed();
    return f;
}

}  // namespace brume
