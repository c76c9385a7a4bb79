// brume raybench SCENE: how close the path tracer comes to Embree's raw ray rate, and how
// well rendering scales with threads. A benchmark, not a test: it prints labelled numbers.
#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

#include "brume/cli/command_line.h"
#include "brume/cli/commands.h"
#include "brume/integrators/path_tracer.h"
#include "brume/film/film.h"
#include "brume/render/renderer.h"
#include "brume/sampling/warp.h"

namespace brume::cli {

namespace {

struct BenchArgs {
    std::string scene;
    int threads = 0;
    int spp = 4;
    Resolution res;
};

const char* const kRaybenchDescription =
    "Renders SCENE with the path tracer and reports its rays/s; traces as many random rays\n"
    "(origins uniform in the scene's bounding sphere, uniform directions) with raw Embree\n"
    "rtcIntersect1 on the same threads and reports their rays/s and the ratio; then renders\n"
    "with 1 thread and with N threads and reports the speed-up.";

// The command line; false if help was asked for (and printed).
bool parseBenchArgs(const std::vector<std::string>& argv, BenchArgs& a) {
    CLI::App app(kRaybenchDescription, "brume raybench");
    configureCommand(app, "SCENE [--threads N] [--spp N] [--res WxH]");
    addSceneArgument(app, a.scene);
    addOption(app, "--threads", "N", "threads (default: all hardware threads)",
              [&](const std::string& v) { a.threads = int(parseInteger("--threads", v, 1, 1024)); });
    addOption(app, "--spp", "N", "samples per pixel of each render (default 4)",
              [&](const std::string& v) { a.spp = int(parseInteger("--spp", v, 1, 1 << 24)); });
    addOption(app, "--res", "WxH", "image size (default as for brume render)",
              [&](const std::string& v) { a.res = parseResolution("--res", v); });
    if (!parseCommand(app, argv)) return false;
    if (a.scene.empty()) throw UsageError("raybench: no scene file given");
    return true;
}

struct RawResult {
    double seconds = 0;
    uint64_t hits = 0;
};

// `count` random rays through the scene's bounding sphere, traced with rtcIntersect1 by
// `threads` threads taking batches from a shared counter.
RawResult traceRandomRays(const Scene& scene, uint64_t count, int threads) {
    constexpr uint64_t kBatch = 4096;
    std::atomic<uint64_t> next{0};
    std::atomic<uint64_t> hits{0};
    const Vec3 center = scene.boundsCenter();
    const float radius = scene.boundsRadius();
    RTCScene rtc = scene.embreeScene();

    auto worker = [&] {
        _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
        _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
        uint64_t localHits = 0;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (uint64_t begin = next.fetch_add(kBatch); begin < count; begin = next.fetch_add(kBatch)) {
            uint64_t end = std::min(count, begin + kBatch);
            Sampler sampler(0x5eed, begin, 0);
            for (uint64_t i = begin; i < end; ++i) {
                Vec3 radial = sampleUniformSphere(sampler.next2D());
                float r = radius * std::cbrt(sampler.next1D());
                Vec3 o = center + radial * r;
                Vec3 d = sampleUniformSphere(sampler.next2D());
                RTCRayHit rh;
                rh.ray.org_x = o.x;
                rh.ray.org_y = o.y;
                rh.ray.org_z = o.z;
                rh.ray.dir_x = d.x;
                rh.ray.dir_y = d.y;
                rh.ray.dir_z = d.z;
                rh.ray.tnear = 0.0f;
                rh.ray.tfar = kInfinity;
                rh.ray.mask = 0xFFFFFFFFu;
                rh.ray.time = 0.0f;
                rh.ray.flags = 0;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(rtc, &context, &rh);
                localHits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            }
        }
        hits.fetch_add(localHits);
    };

    auto start = std::chrono::steady_clock::now();
    std::vector<std::thread> pool;
    for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
    for (std::thread& t : pool) t.join();
    RawResult result;
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.hits = hits.load();
    return result;
}

RenderStats renderOnce(const Scene& scene, Integrator& integrator, Resolution res, int spp, int threads) {
    RenderOptions options;
    options.width = res.width;
    options.height = res.height;
    options.spp = spp;
    options.threads = threads;
    Film film(res.width, res.height);
    return render(scene, integrator, options, film);
}

double perSecond(double amount, double seconds) { return amount / (seconds > 0 ? seconds : 1e-9); }

}  // namespace

int runRaybench(const std::vector<std::string>& argv) {
    BenchArgs a;
    if (!parseBenchArgs(argv, a)) return kExitOk;
    SceneDescription desc = loadSceneDescription(a.scene);
    Resolution res = imageResolution(desc.camera, a.res);
    Scene scene(std::move(desc));
    PathTracer integrator{PathTracerOptions{}};
    int threads = a.threads > 0 ? a.threads : std::max(1, int(std::thread::hardware_concurrency()));

    std::printf("threads %d\nresolution %dx%d\nspp %d\n", threads, res.width, res.height, a.spp);
    std::fflush(stdout);

    RenderStats pt = renderOnce(scene, integrator, res, a.spp, threads);
    double ptRate = perSecond(double(pt.rays), pt.seconds);
    std::printf("pt_rays %llu\npt_seconds %.3f\npt_rays_per_second %.0f\n",
                static_cast<unsigned long long>(pt.rays), pt.seconds, ptRate);
    std::fflush(stdout);

    // As many raw rays as the path tracer traced (at least 2^21, for a stable rate).
    uint64_t rawCount = std::max<uint64_t>(pt.rays, uint64_t(1) << 21);
    RawResult raw = traceRandomRays(scene, rawCount, threads);
    double rawRate = perSecond(double(rawCount), raw.seconds);
    std::printf("embree_rays %llu\nembree_hit_fraction %.3f\nembree_seconds %.3f\nembree_rays_per_second %.0f\n",
                static_cast<unsigned long long>(rawCount), double(raw.hits) / double(rawCount), raw.seconds,
                rawRate);
    std::printf("pt_to_embree_ratio %.3f\n", ptRate / rawRate);
    std::fflush(stdout);

    RenderStats one = renderOnce(scene, integrator, res, a.spp, 1);
    std::printf("render_seconds_1_thread %.3f\n", one.seconds);
    std::fflush(stdout);
    RenderStats many = renderOnce(scene, integrator, res, a.spp, threads);
    std::printf("render_seconds_n_threads %.3f\n", many.seconds);
    std::printf("speedup %.2f\n", one.seconds / (many.seconds > 0 ? many.seconds : 1e-9));
    return kExitOk;
}

}  // namespace brume::cli
