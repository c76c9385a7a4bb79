#include "brume/integrators/denoise_features.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

#include "brume/integrators/boundary_walk.h"
#include "brume/integrators/path_stats.h"
#include "brume/sampling/sampler.h"

namespace brume {

namespace {

struct Feature {
    Spectrum albedo{0.0f};
    Vec3 normal{0.0f};
};

Feature firstHit(const Scene& scene, const Ray& ray, PathStats& stats) {
    Feature f;
    Spectrum T(1.0f);  // the probability, per channel, that the ray has met nothing yet
    BoundaryWalk walk(scene, leaving(ray.o, Vec3(0.0f), ray.d), scene.cameraMedia(), stats);
    BoundaryPiece piece;
    while (walk.next(&piece)) {
        if (piece.medium && maxComponent(piece.medium->sigmaT()) > 0) {
            // Its expected share: collisions in this piece, 1 − T over it.
            const Spectrum st = piece.medium->sigmaT(), ss = piece.medium->sigmaS;
            // (A homogeneous piece to infinity: met surely in every channel that has extinction.
            // A grid medium's ends where the ray leaves its grid.)
            Spectrum Tp;
            if (std::isinf(piece.t1) && !piece.medium->heterogeneous())
                for (int c = 0; c < 3; ++c) Tp[c] = st[c] > 0 ? 0.0f : 1.0f;
            else
                Tp = piece.medium->transmittance(ray, piece.t0, piece.t1);
            float meet = 0;
            for (int c = 0; c < 3; ++c) {
                const float m = T[c] * (1 - Tp[c]);
                f.albedo[c] += m * (st[c] > 0 ? ss[c] / st[c] : 0.0f);
                meet += m / 3;
                T[c] *= Tp[c];
            }
            f.normal += -ray.d * meet;
        }
        if (piece.hit.valid() && !piece.boundary) {
            const SurfaceHit& h = piece.hit;
            if (h.sphereLight >= 0) return f;  // a sphere light: no surface colour
            f.albedo += T * scene.surfaceBsdf(h.mesh, h.u, h.v, h.ng, h.ns).albedo();
            f.normal += (dot(h.ns, ray.d) > 0 ? -h.ns : h.ns) * ((T.x + T.y + T.z) / 3);
            return f;
        }
        if (isBlack(T)) return f;
    }
    return f;
}

}  // namespace

DenoiseFeatures denoiseFeatures(const Scene& scene, int width, int height, uint64_t seed, int threads) {
    DenoiseFeatures out;
    out.albedo.assign(size_t(width) * size_t(height) * 3, 0.0f);
    out.normal = out.albedo;
    std::atomic<int> nextRow{0};
    auto work = [&] {
        PathStats stats;
        for (int y; (y = nextRow++) < height;)
            for (int x = 0; x < width; ++x) {
                Rng rng(mixBits(seed ^ mixBits((uint64_t(y) << 32) | uint32_t(x))), 0xae0);
                Spectrum albedo(0.0f);
                Vec3 normal(0.0f);
                for (int k = 0; k < DenoiseFeatures::kSamples; ++k) {
                    const Sample2 j = rng.next2D();
                    const Ray ray = scene.camera().generateRay(x + j.u, y + j.v, width, height);
                    const Feature f = firstHit(scene, ray, stats);
                    albedo += f.albedo;
                    normal += f.normal;
                }
                const size_t i = 3 * (size_t(y) * size_t(width) + size_t(x));
                for (int c = 0; c < 3; ++c) {
                    out.albedo[i + size_t(c)] = albedo[c] / DenoiseFeatures::kSamples;
                    out.normal[i + size_t(c)] = normal[c] / DenoiseFeatures::kSamples;
                }
            }
    };
    const int n = std::max(1, std::min(threads > 0 ? threads : int(std::thread::hardware_concurrency()), height));
    std::vector<std::thread> pool;
    for (int t = 1; t < n; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    return out;
}

}  // namespace brume
