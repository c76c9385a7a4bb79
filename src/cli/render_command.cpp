// brume render SCENE -o OUT [options]: everything is checked before the first sample, the
// image is written in one piece at the end, and a summary line goes to stdout.
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <memory>
#include <new>
#include <optional>
#include <stdexcept>

#include "brume/cli/command_line.h"
#include "brume/cli/commands.h"
#include "brume/cli/distributed_render.h"
#include "brume/integrators/allocation_planner.h"
#include "brume/integrators/direct_light_tracing.h"
#include "brume/integrators/bdpt.h"
#include "brume/integrators/denoise_features.h"
#include "brume/integrators/integrator_settings.h"
#include "brume/integrators/path_tracer.h"
#include "brume/render/checkpoint.h"
#include "brume/film/film.h"
#include "brume/film/pixel_noise.h"
#include "brume/render/fnv1a.h"
#include "brume/cli/scene_identity.h"
#include "brume/film/image_io.h"
#include "brume/render/renderer.h"

namespace brume::cli {

namespace {

// --stats: each technique's share of the image and of the summed squares of its per-sample
// contributions to a pixel (technique_sums.h). (The squares hold each pixel's squared mean
// too: a share of them well above the share of the image marks a noisy technique; a nearly
// exact one has about its share of the image squared, relative to the others.)
std::string techniqueShares(const TechniqueSums& t) {
    static const char* const kNames[TechniqueSums::kSlots] = {
        "emitter hit",           "",  // (no equi-angular variant)
        "light connection",      "light connection, equi-angular",
        "camera connection",     "camera connection, equi-angular",
        "general connection",    "general connection, equi-angular",
        "path tracer: emitter hit", "path tracer: light connection at a vertex",
        "path tracer: light connection on a segment", "path tracer: light connection by solid angle"};
    double sum = 0, squares = 0;
    for (int k = 0; k < TechniqueSums::kSlots; ++k) sum += t.sum[k], squares += t.squares[k];
    if (!(sum > 0) || !(squares > 0)) return "";
    std::string out = "  technique (share of the image, of the squares)\n";
    for (int k = 0; k < TechniqueSums::kSlots; ++k) {
        if (t.sum[k] == 0 && t.squares[k] == 0) continue;
        char line[160];
        std::snprintf(line, sizeof line, "  %-46s %6.4f %6.4f\n", kNames[k], t.sum[k] / sum, t.squares[k] / squares);
        out += line;
    }
    return out;
}

std::string fixed4(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}

// --stats: what a sample did, per part (the counters the duel's costs are counted from).
std::string workPerSample(const std::string& integrator, const RenderStats& st) {
    const double n = double(std::max<uint64_t>(st.samples, 1));
    auto per = [&](uint64_t count) { return double(count) / n; };
    const PathTracerCounts& pt = st.counts.pt;
    const BidirectionalCounts& b = st.counts.bdpt;
    char buf[512];
    if (integrator == "pt")
        std::snprintf(buf, sizeof buf,
                      "work per sample: walk rays %.3f; light connections at vertices %.3f (%.3f rays), on segments %.3f "
                      "(%.3f rays), by solid angle %.3f (%.3f rays)\n",
                      per(pt.walkRays), per(pt.vertexCalls), per(pt.vertexRays), per(pt.segmentCalls), per(pt.segmentRays),
                      per(pt.solidAngleCalls), per(pt.solidAngleRays));
    else
        std::snprintf(buf, sizeof buf,
                      "work per sample: camera walk rays %.3f, light walk rays %.3f; light connections %.3f + %.3f "
                      "equi-angular rays, camera connections %.3f + %.3f, general connections %.3f + %.3f\n",
                      per(b.cameraWalkRays), per(b.lightWalkRays), per(b.rays(StrategyKind::LightConnection, false)),
                      per(b.rays(StrategyKind::LightConnection, true)), per(b.rays(StrategyKind::CameraConnection, false)),
                      per(b.rays(StrategyKind::CameraConnection, true)), per(b.rays(StrategyKind::SubpathConnection, false)),
                      per(b.rays(StrategyKind::SubpathConnection, true)));
    std::string out = buf;
    // Samples the path tracer made inside the bidirectional tracer: auto's path tracer, and
    // the camera family of the single-scattering split (one_event_split.h), whose light
    // tracing is counted above as the light walk and camera connections.
    if (integrator != "pt" && pt.samples > 0) {
        std::snprintf(buf, sizeof buf,
                      "  by the path tracer inside, %.3f of the samples: walk rays %.3f; light connections at vertices "
                      "%.3f (%.3f rays), on segments %.3f (%.3f rays), by solid angle %.3f (%.3f rays)\n",
                      per(pt.samples), per(pt.walkRays), per(pt.vertexCalls), per(pt.vertexRays), per(pt.segmentCalls),
                      per(pt.segmentRays), per(pt.solidAngleCalls), per(pt.solidAngleRays));
        out += buf;
    }
    return out + techniqueShares(st.techniques);
}


struct RenderArgs {
    std::string scene;
    std::string output;
    std::string integrator = "auto";
    std::string allocation;  // --allocation NAME (bdpt)
    bool stats = false;      // --stats
    int spp = 16;
    bool sppGiven = false;
    double seconds = 0;
    int maxDepth = -1;
    bool maxDepthGiven = false;
    bool nee = true;
    ConnectMode connect = ConnectMode::Mis;
    bool guiding = false;    // --guiding on (pt)
    // --guiding auto (the default; guide_start.h): pt, and auto once it has chosen the path
    // tracer, start a guide where enough passes follow. Resolved to off with --noise-threshold
    // (not with --target-error, whose estimate of the render's length the guide reads),
    // with --strategy-images and under mpirun with --time.
    bool guidingAuto = true;
    std::string guidingChoice = "auto";  // as given, for checkpoints
    int guidedDistances = -1;  // --guided-distances: the deepest vertex whose rays are guided (−1: off)
    bool volumeLights = true;  // --volume-lights
    EmitterSampling emitters = EmitterSampling::SolidAngle;
    MisHeuristic heuristic = MisHeuristic::Power;
    std::string strategyDir;
    Resolution res;  // width 0: from the camera
    uint64_t seed = 0;
    SamplerKind sampler = SamplerKind::Sobol;
    int threads = 0;
    std::string checkpoint;       // --checkpoint FILE
    double checkpointEvery = 60;  // seconds
    bool checkpointEveryGiven = false;
    double writeEvery = 0;        // --write-every SECONDS (0: only at the end)
    double noiseThreshold = 0;    // --noise-threshold E, or --target-error E (0: off)
    // The threshold is the whole image's (--target-error, or the default rule): every pixel
    // takes every pass until the image's estimated relative error reaches it.
    bool wholeImage = false;
    bool defaultRule = false;     // neither --spp, --time nor a threshold given, nor the scene's spp
    bool aovAlbedo = false, aovNormal = false, aovVariance = false;  // --aov
    std::string resume;           // --resume FILE
    int stopAfterPasses = -1;     // testing only: as if SIGTERM came after N passes of this run
    int failRank = -1, failPass = -1;  // testing only: that rank fails at that pass (PassPlan)
};

// The most passes adaptive stopping renders when neither --spp nor --time bounds it.
constexpr int kAdaptiveMaxSpp = 1024;
// The default rule of `brume render` (no --spp, --time or threshold, and no spp in the scene),
// as Cycles stops at a noise threshold by default: every pixel takes every pass until the
// image's estimated relative error is 0.1 (relative MSE 0.01), at most kAdaptiveMaxSpp
// passes. No time limit by default: it would make the image depend on the machine's speed.
constexpr double kDefaultTargetError = 0.1;

// A number as a checkpoint setting: the fewest digits that read back as the same double.
std::string numberText(double v) {
    char buf[32];
    for (int digits = 1; digits <= 17; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}

const char* const kRenderDescription =
    "Renders a glTF scene and writes OUT (.exr: float linear RGB, .pfm: float linear RGB,\n"
    ".png: 8-bit sRGB).";

const char* const kRenderFooter =
    "SIGINT (Ctrl-C) and SIGTERM abandon the pass in flight, write the image of the passes\n"
    "completed (and the checkpoint, with --checkpoint) and exit with 130 (SIGINT) or 143\n"
    "(SIGTERM); if no pass was completed nothing is written. A second signal kills at once.\n"
    "The summary line gives the size, spp, seconds, samples/s, rays/s, non-finite samples\n"
    "dropped and the peak memory.";

std::string nonEmptyFile(const std::string& what, const std::string& file) {
    if (file.empty()) throw UsageError(what + ": empty file name");
    return file;
}

// The command line; false if help was asked for (and printed).
bool parseRenderArgs(const std::vector<std::string>& argv, RenderArgs& a) {
    CLI::App app(kRenderDescription, "brume render");
    configureCommand(app, "SCENE -o OUT [options]");
    app.footer(kRenderFooter);
    addSceneArgument(app, a.scene);
    addOption(app, "-o,--output", "OUT", "output image (required)",
              [&](const std::string& v) { a.output = nonEmptyFile("--output", v); });
    addOption(app, "--integrator", "NAME",
              "auto (the default: the bidirectional path tracer choosing its strategies and their sample counts "
              "from pilot passes), bdpt (bidirectional path tracer, every strategy on) or pt (volumetric path tracer)",
              [&](const std::string& v) { a.integrator = v; });
    addOption(app, "--allocation", "NAME",
              "bdpt: render with this one of auto's candidate allocations (names as --stats lists them, e.g. "
              "'pt+ea' or 'bdpt lt p=0.25 ea=LC')",
              [&](const std::string& v) { a.allocation = v; });
    app.add_flag_callback("--stats", [&] { a.stats = true; },
                          "auto: after the summary line, every candidate allocation's estimated relative variance, "
                          "cost and efficiency, and the duel's measurements; bdpt (and auto in single scattering): light "
                          "tracing's learned share of one-scattering paths; every integrator: the work per sample by part, and each "
                          "technique's share of the image and of the squares of its contributions to a pixel");
    addOption(app, "--mis", "HEURISTIC", "bdpt: power (the default) or balance", [&](const std::string& v) {
        if (v == "power") a.heuristic = MisHeuristic::Power;
        else if (v == "balance") a.heuristic = MisHeuristic::Balance;
        else throw UsageError("--mis: unknown heuristic '" + v + "' (power or balance)");
    });
    addOption(app, "--strategy-images", "DIR",
              "bdpt: also write DIR/s<S>_t<T>.exr, each strategy's weighted contribution (they add up to "
              "the image, with the learned share of light tracing from the first pass; one extra render "
              "each, for s + t - 2 up to min(max-depth, 5)); with --connect "
              "equiangular or mis, s<S>_t<T>_ff.exr and s<S>_t<T>_ea.exr, the free-flight and "
              "equi-angular variants, instead",
              [&](const std::string& v) { a.strategyDir = v; });
    addOption(app, "--spp", "N",
              "samples per pixel (default: the scene's, else until the image's estimated relative error is 0.1, "
              "at most 1024: --target-error; 16 under mpirun or with --strategy-images)", [&](const std::string& v) {
        a.spp = int(parseInteger("--spp", v, 1, 1 << 24));
        a.sppGiven = true;
    });
    addOption(app, "--time", "SECONDS",
              "render whole passes until SECONDS are spent instead of --spp (in single scattering it may end a block of "
              "passes sooner, on a pass count whose binary digits below the top three are 0: README)",
              [&](const std::string& v) { a.seconds = parsePositiveSeconds("--time", v, 1e7); });
    addOption(app, "--max-depth", "N", "most scattering events per path (default -1: unlimited)",
              [&](const std::string& v) {
                  a.maxDepth = int(parseInteger("--max-depth", v, -1, 1000000));
                  a.maxDepthGiven = true;
              });
    app.add_flag_callback("--no-nee", [&] { a.nee = false; }, "no next-event estimation (BSDF/phase sampling only)");
    addOption(app, "--connect", "MODE",
              "light connections on medium segments: density (from the free-flight point), equiangular, "
              "product (equi-angular x phase in anisotropic media), or mis (density and product; the "
              "default; pt makes each, or leaves one out, as its first 8 passes show it pays; C always beside a point light in fog); for bdpt: "
              "equi-angular variants of connection vertices",
              [&](const std::string& v) {
                  if (v == "density") a.connect = ConnectMode::Density;
                  else if (v == "equiangular") a.connect = ConnectMode::EquiAngular;
                  else if (v == "product") a.connect = ConnectMode::Product;
                  else if (v == "mis") a.connect = ConnectMode::Mis;
                  else throw UsageError("--connect: unknown mode '" + v + "' (density, equiangular, product or mis)");
              });
    addOption(app, "--emitter-sampling", "HOW",
              "light points on emissive triangles: solid-angle (uniform in the solid angle they subtend, "
              "and with --connect mis distances sampled by that solid angle in fog; the default) or area "
              "(uniform by area, the light point first)",
              [&](const std::string& v) { a.emitters = parseEmitterSampling("--emitter-sampling", v); });
    addOption(app, "--res", "WxH",
              "image size (default 640 wide, height from the camera's aspect ratio, 640x480 without one)",
              [&](const std::string& v) { a.res = parseResolution("--res", v); });
    addOption(app, "--seed", "N", "random seed (default 0); the same seed gives the same image for any thread count",
              [&](const std::string& v) { a.seed = parseUnsigned64("--seed", v); });
    addOption(app, "--sampler", "NAME",
              "sobol (Owen-scrambled Sobol, low discrepancy; the default) or independent (white noise)",
              [&](const std::string& v) { a.sampler = parseSamplerKind("--sampler", v); });
    addOption(app, "--threads", "N", "worker threads (default: all hardware threads)",
              [&](const std::string& v) { a.threads = int(parseInteger("--threads", v, 1, 1024)); });
    addOption(app, "--guiding", "on|off|auto",
              "path guiding from a radiance field learned in 16 training passes (docs/path-guiding.md): pt draws "
              "directions from it, combined with phase and BSDF sampling, and both pt and bdpt end walks by what "
              "it expects them to bring (guided survival; bdpt: the camera walk, after 16 training passes of "
              "pt). on: pt and bdpt from the first pass; auto (the default): pt, and auto once it has chosen "
              "the path tracer, start learning where at least 64 passes are still to come (--spp, the time "
              "left at the pace of the last pass, or the length a target error's estimate predicts), not in single scattering (--max-depth 0 or 1), with "
              "--noise-threshold or --strategy-images, or under mpirun with --time",
              [&](const std::string& v) {
                  if (v != "on" && v != "off" && v != "auto")
                      throw UsageError("--guiding: expected on, off or auto, got '" + v + "'");
                  a.guiding = v == "on";
                  a.guidingAuto = v == "auto";
                  a.guidingChoice = v;
              });
    addOption(app, "--guided-distances", "off|camera|all",
              "with --integrator pt --guiding on: collisions drawn by the learned in-scattered radiance, "
              "MIS-combined with free flight, on camera rays or on every ray, in homogeneous grey media "
              "(docs/path-guiding.md); off by default (on the scenes measured it cost more than it gave)",
              [&](const std::string& v) {
                  if (v == "off") a.guidedDistances = -1;
                  else if (v == "camera") a.guidedDistances = 0;
                  else if (v == "all") a.guidedDistances = 1 << 30;
                  else throw UsageError("--guided-distances: expected off, camera or all, got '" + v + "'");
              });
    addOption(app, "--volume-lights", "on|off",
              "pt, bdpt (without coloured media) and auto sample points of glowing media with emission grids "
              "as lights, MIS-combined with the emission the camera paths gather (docs/mis.md); on by default",
              [&](const std::string& v) {
                  if (v == "on") a.volumeLights = true;
                  else if (v == "off") a.volumeLights = false;
                  else throw UsageError("--volume-lights: expected on or off, got '" + v + "'");
              });
    addOption(app, "--checkpoint", "FILE",
              "save the render's state to FILE every --checkpoint-every seconds and when interrupted "
              "(written beside FILE and renamed into place; removed once the image is complete); needs --spp",
              [&](const std::string& v) { a.checkpoint = nonEmptyFile("--checkpoint", v); });
    addOption(app, "--checkpoint-every", "SECONDS", "seconds between checkpoints (default 60)",
              [&](const std::string& v) {
                  a.checkpointEvery = parsePositiveSeconds("--checkpoint-every", v, 1e7);
                  a.checkpointEveryGiven = true;
              });
    addOption(app, "--noise-threshold", "E",
              "adaptive sampling: render until the image's estimated relative error (the square root of its "
              "relative MSE as bench weighs errors) is E, each pixel taking as many passes as reach that soonest "
              "(chosen at passes 16, 20, 24, 28, 32, 40, ...); --spp or --time bound it (default: at most " +
                  std::to_string(kAdaptiveMaxSpp) + " spp); docs/adaptive-sampling.md",
              [&](const std::string& v) {
                  if (a.wholeImage) throw UsageError("--noise-threshold and --target-error exclude each other");
                  a.noiseThreshold = parsePositiveNumber("--noise-threshold", v, 1e6);
              });
    addOption(app, "--target-error", "E",
              "render every pixel until the whole image's estimated relative error (as --noise-threshold "
              "estimates it) is E, checked at the same passes; --spp or --time bound it (default: at most " +
                  std::to_string(kAdaptiveMaxSpp) + " spp). Without --spp, --time or a threshold (and no spp in "
                  "the scene) brume render stops so at 0.1; docs/adaptive-sampling.md",
              [&](const std::string& v) {
                  if (a.noiseThreshold > 0 && !a.wholeImage) throw UsageError("--noise-threshold and --target-error exclude each other");
                  a.noiseThreshold = parsePositiveNumber("--target-error", v, 1e6);
                  a.wholeImage = true;
              });
    addOption(app, "--write-every", "SECONDS",
              "also write OUT every SECONDS while rendering, the image of the passes so far (beside OUT and "
              "renamed into place), to watch a long render; the final image is the same",
              [&](const std::string& v) { a.writeEvery = parsePositiveSeconds("--write-every", v, 1e7); });
    addOption(app, "--aov", "LIST",
              "also write these layers into the EXR, for denoisers (docs/denoising.md): albedo, normal, "
              "variance (of each pixel's mean, from the spread of its passes; not under mpirun) (comma-separated)",
              [&](const std::string& v) {
                  size_t at = 0;
                  while (at <= v.size()) {
                      const size_t comma = std::min(v.find(',', at), v.size());
                      const std::string name = v.substr(at, comma - at);
                      if (name == "albedo") a.aovAlbedo = true;
                      else if (name == "normal") a.aovNormal = true;
                      else if (name == "variance") a.aovVariance = true;
                      else throw UsageError("--aov: unknown layer '" + name + "' (available: albedo, normal, variance)");
                      at = comma + 1;
                  }
              });
    addOption(app, "--resume", "FILE",
              "continue the render saved in checkpoint FILE: the result is the same, bit for bit, as one that "
              "never stopped; scene file, --res, --seed, --spp, --integrator, --connect, --max-depth, --mis, "
              "--no-nee, --guiding, --guided-distances and --volume-lights must be as before (use the same FILE for --checkpoint to keep saving)",
              [&](const std::string& v) { a.resume = nonEmptyFile("--resume", v); });
    // For tests: as if SIGTERM came after N passes. No description: not in the help.
    addOption(app, "--stop-after-passes", "N", "",
              [&](const std::string& v) { a.stopAfterPasses = int(parseInteger("--stop-after-passes", v, 0, 1 << 24)); });
    // For tests: rank RANK (under mpirun) fails as it starts pass PASS. Not in the help.
    addOption(app, "--fail-at-pass", "RANK:PASS", "", [&](const std::string& v) {
        const size_t colon = v.find(':');
        if (colon == std::string::npos) throw UsageError("--fail-at-pass: expected RANK:PASS, got '" + v + "'");
        a.failRank = int(parseInteger("--fail-at-pass", v.substr(0, colon), 0, 1 << 20));
        a.failPass = int(parseInteger("--fail-at-pass", v.substr(colon + 1), 0, 1 << 24));
    });
    if (!parseCommand(app, argv)) return false;

    if (a.scene.empty()) throw UsageError("render: no scene file given");
    if (a.output.empty()) throw UsageError("render: no output file given (-o OUT)");
    IntegratorKind kind;
    if (!integratorKindNamed(a.integrator, &kind))
        throw UsageError("unknown integrator '" + a.integrator + "' (available: auto, bdpt, pt)");
    if (!a.allocation.empty()) {
        if (a.integrator != "bdpt") throw UsageError("--allocation needs --integrator bdpt");
        BdptAllocation chosen;
        if (!allocationNamed(a.allocation, a.connect, &chosen)) {
            std::string names;
            for (const BdptAllocation& c : candidateAllocations(a.connect)) names += (names.empty() ? "'" : ", '") + c.name() + "'";
            throw UsageError("--allocation: unknown allocation '" + a.allocation + "' (available: " + names + ")");
        }
    }
    if (a.guiding && a.integrator == "auto") throw UsageError("--guiding on needs --integrator pt or bdpt");
    if (a.guiding && !a.strategyDir.empty()) throw UsageError("--strategy-images and --guiding on exclude each other");
    if (a.guidedDistances >= 0 && !(a.guiding && a.integrator == "pt"))
        throw UsageError("--guided-distances needs --integrator pt --guiding on");
    if (a.sppGiven && a.seconds > 0) throw UsageError("--spp and --time exclude each other");
    if (a.noiseThreshold > 0 && !a.sppGiven && a.seconds <= 0) {
        a.spp = kAdaptiveMaxSpp;
        a.sppGiven = true;  // (the scene's spp does not stand in: the threshold ends the render)
    }
    if (a.noiseThreshold > 0 && !a.strategyDir.empty())
        throw UsageError(std::string("--strategy-images and ") + (a.wholeImage ? "--target-error" : "--noise-threshold") + " exclude each other");
    // A guide started mid-render would learn from passes whose stopped pixels are black, and
    // strategy images re-render passes by strategy: --guiding auto leaves both unguided.
    // (A target error for the whole image tells the guide how long the render will be:
    // guide_start.h.)
    if ((a.noiseThreshold > 0 && !a.wholeImage) || !a.strategyDir.empty()) a.guidingAuto = false;
    if (!a.strategyDir.empty() && a.integrator == "pt") throw UsageError("--strategy-images needs --integrator bdpt or auto");
    if (!a.strategyDir.empty() && a.seconds > 0) throw UsageError("--strategy-images needs --spp, not --time");
    // Checkpoints are for a planned number of passes: a time budget has no fixed end to resume to.
    if (a.checkpointEveryGiven && a.checkpoint.empty()) throw UsageError("--checkpoint-every needs --checkpoint FILE");
    if (!a.checkpoint.empty() && a.seconds > 0) throw UsageError("--checkpoint needs --spp, not --time");
    if (!a.resume.empty() && a.seconds > 0) throw UsageError("--resume needs --spp, not --time");
    if (!a.checkpoint.empty() && a.checkpoint == a.output)
        throw UsageError("--checkpoint and --output name the same file '" + a.output + "'");
    if ((a.aovAlbedo || a.aovNormal || a.aovVariance) && a.output.size() >= 4 && a.output.compare(a.output.size() - 4, 4, ".exr") != 0 &&
        a.output.compare(a.output.size() - 4, 4, ".EXR") != 0)
        throw UsageError("--aov needs an .exr output (the layers go into it)");
    return true;
}

std::atomic<bool> gInterrupted{false};
std::atomic<int> gSignal{0};  // the first signal caught

// One render per strategy (s, t), same seed and spp, each keeping only that strategy's
// weighted contribution: the images add up to the full render.
void writeStrategyImages(const Scene& scene, BdptOptions bdpt, RenderOptions options, const std::string& dir) {
    ::mkdir(dir.c_str(), 0777);
    const int maxDepth = bdpt.maxDepth < 0 ? 5 : std::min(bdpt.maxDepth, 5);
    options.progress = false;
    bdpt.hooks.weighted = true;
    for (int depth = 0; depth <= maxDepth; ++depth)
        for (int s = 0; s <= depth + 2; ++s) {
            int t = depth + 2 - s;
            if (t < 1) continue;
            bdpt.hooks.onlyS = s;
            bdpt.hooks.onlyT = t;
            // With equi-angular connections each strategy has two variants, one image each.
            const bool variants = bdpt.connect != ConnectMode::Density;
            for (int variant = variants ? 0 : -1; variant <= (variants ? 1 : -1); ++variant) {
                bdpt.hooks.onlyVariant = variant;
                BdptIntegrator integrator(bdpt);
                Film film(options.width, options.height);
                render(scene, integrator, options, film, &gInterrupted);
                if (gInterrupted.load()) return;
                std::string path = dir + "/s" + std::to_string(s) + "_t" + std::to_string(t) +
                                   (variant == 0 ? "_ff" : variant == 1 ? "_ea" : "") + ".exr";
                writeImage(path, options.width, options.height, film.rgb());
            }
        }
    std::printf("strategy images in %s\n", dir.c_str());
}

extern "C" void onSignal(int sig) {
    int none = 0;
    gSignal.compare_exchange_strong(none, sig);
    gInterrupted.store(true);
}

// The first SIGINT or SIGTERM asks the renderer to stop (see kRenderFooter); SA_RESETHAND
// makes a second one kill the process as usual. SA_RESTART keeps the file writes going.
void catchSignals() {
    struct sigaction sa {};
    sa.sa_handler = onSignal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND | SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

// 128 + the signal number, as a shell reports a process killed by it: 130 and 143.
int exitCodeFor(int sig) { return sig == SIGTERM ? 128 + SIGTERM : kExitInterrupted; }
const char* signalName(int sig) { return sig == SIGTERM ? "SIGTERM" : "SIGINT"; }

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// ru_maxrss is in KiB on Linux.
double peakMemoryMiB() {
    struct rusage usage {};
    ::getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;
}

const char* connectName(ConnectMode mode) {
    switch (mode) {
    case ConnectMode::Density: return "density";
    case ConnectMode::EquiAngular: return "equiangular";
    case ConnectMode::Product: return "product";
    default: return "mis";
    }
}

// Everything that changes the image's bits (not --threads): a checkpoint continues only
// under the same settings. The scene: every file it was read from (scene_identity.h).
CheckpointSettings checkpointSettings(const RenderArgs& a, Resolution res, const SceneDescription& scene) {
    CheckpointSettings settings = sceneFileSettings(scene);
    const CheckpointSettings options = {
            {"--res", std::to_string(res.width) + "x" + std::to_string(res.height)},
            {"--seed", std::to_string(a.seed)},
            {"--sampler", samplerName(a.sampler)},
            {"--spp", std::to_string(a.spp)},
            {"--integrator", a.integrator},
            {"--allocation", a.allocation},
            {"--connect", connectName(a.connect)},
            {"--emitter-sampling", emitterSamplingName(a.emitters)},
            {"--max-depth", std::to_string(a.maxDepth)},
            {"--guiding", a.guidingChoice},
            {"--guided-distances", a.guidedDistances < 0 ? "off" : (a.guidedDistances == 0 ? "camera" : "all")},
            {"--volume-lights", a.volumeLights ? "on" : "off"},
            {"--mis", a.heuristic == MisHeuristic::Balance ? "balance" : "power"},
            {"next-event estimation (--no-nee)", a.nee ? "on" : "off"}};
    settings.insert(settings.end(), options.begin(), options.end());
    if (a.noiseThreshold > 0) settings.push_back({a.wholeImage ? "--target-error" : "--noise-threshold", numberText(a.noiseThreshold)});
    if (a.aovVariance) settings.push_back({"the variance layer (--aov variance)", "on"});
    return settings;
}

// Throws std::runtime_error (one line, exit code 1) unless `saved` continues this render.
void checkResumable(const std::string& file, const Checkpoint& saved, const CheckpointSettings& now,
                    Resolution res, int spp) {
    std::string mismatch = checkpointMismatch(saved.settings, now);
    if (!mismatch.empty()) {
        if (mismatch.rfind("the scene file", 0) == 0 || mismatch.rfind("the FNV-1a hash of", 0) == 0 ||
            mismatch.rfind("the checkpoint has the FNV-1a hash of", 0) == 0)
            mismatch += " (it was made from " + saved.scenePath + ")";
        throw std::runtime_error(file + ": cannot resume this render: " + mismatch);
    }
    if (saved.film.width() != res.width || saved.film.height() != res.height || saved.film.passes() > spp)
        throw std::runtime_error(file + ": corrupt checkpoint (film does not match its settings)");
}

std::string absolutePath(const std::string& path) {
    std::error_code ec;
    std::filesystem::path p = std::filesystem::absolute(path, ec);
    return ec ? path : p.lexically_normal().string();
}

}  // namespace

namespace {

// What an error says, for a line of stderr.
std::string errorText(std::exception_ptr error) {
    try {
        std::rethrow_exception(error);
    } catch (const std::bad_alloc&) {
        return "out of memory";
    } catch (const std::exception& e) {
        return e.what();
    } catch (...) {
        return "an unknown error";
    }
}

// After a step of the set-up that may fail on some ranks alone (loading the scene, whose files
// each rank reads where it runs; rank 0's checkpoint; the state rank 0 sends): where it failed
// on some rank, rank 0 reports its own error, and a rank that failed where rank 0 did not
// reports its own, naming itself (rank 0 alone could not say why). The exit code to return, or
// −1 to go on. (A collective: every rank calls it, before any other collective can wait for a
// rank that failed.)
int agreeAfterSetup(const RankGroup& group, std::exception_ptr error) {
    if (group.allOk(!error)) return -1;
    const bool leadFailed = group.broadcast(group.rank() == 0 && error ? "1" : "0") == "1";
    if (error && group.rank() == 0) std::rethrow_exception(error);
    if (error && !leadFailed) std::fprintf(stderr, "brume: rank %d: %s\n", group.rank(), errorText(error).c_str());
    return kExitFailure;
}

// The render on this process; with several ranks, see distributed_render.h. Ranks other than
// 0 check what they use themselves (arguments, scene) and leave the files to rank 0.
// Loads the scene (its BRUME_render settings stand in for the options not given) and, under
// mpirun, checks that every rank has the same arguments and scene file. The exit code to
// return, or −1 to go on.
int loadAgreedScene(const RankGroup& group, const std::vector<std::string>& argv, RenderArgs& a,
                    std::optional<Scene>& sceneStorage, Resolution& res) {
    const bool lead = group.rank() == 0;
    std::exception_ptr setupError;
    try {
        SceneDescription desc = loadSceneDescription(a.scene, lead);  // (warnings once, from rank 0)
        // The scene's BRUME_render settings stand in for the options not given.
        if (a.res.width == 0 && desc.render.width > 0) a.res = Resolution{desc.render.width, desc.render.height};
        if (!a.sppGiven && a.seconds <= 0 && desc.render.spp > 0) a.spp = desc.render.spp;
        // The default rule: neither --spp, --time, a threshold nor the scene's spp (not under
        // mpirun, whose films keep no squares, nor for strategy images: 16 passes there).
        if (!a.sppGiven && a.seconds <= 0 && desc.render.spp <= 0 && a.noiseThreshold <= 0 && a.strategyDir.empty() &&
            !group.distributed()) {
            a.noiseThreshold = kDefaultTargetError;
            a.wholeImage = a.defaultRule = true;
            a.spp = kAdaptiveMaxSpp;
        }
        if (!a.maxDepthGiven && desc.render.maxDepth >= -1) a.maxDepth = desc.render.maxDepth;
        res = imageResolution(desc.camera, a.res);
        sceneStorage.emplace(std::move(desc));
        sceneStorage->setEmitterSampling(a.emitters);
    } catch (...) {
        setupError = std::current_exception();
    }
    if (const int exit = agreeAfterSetup(group, setupError); exit >= 0) return exit;
    if (group.distributed()) {
        // Every rank must render the same thing: its arguments and its scene file's bytes.
        Fnv1a64 h;
        const uint64_t sceneHash = sceneContentHash(sceneStorage->desc());  // every file (scene_identity.h)
        h.add(&sceneHash, sizeof sceneHash);
        for (const std::string& arg : argv) h.add(arg.c_str(), arg.size() + 1);  // (with its terminator)
        const uint64_t key = h.value();
        std::vector<int> differing = group.ranksDiffering(key);
        std::string which;
        for (int r : differing) which += (which.empty() ? "" : ", ") + std::to_string(r);
        const bool same = group.allOk(differing.empty());
        if (!same) {
            if (lead)
                throw UsageError("rank" + std::string(differing.size() > 1 ? "s " : " ") + which +
                                 " started with other arguments or another scene file than rank 0");
            return kExitUsage;
        }
    }
    return -1;
}

// The integrator the arguments ask for.
IntegratorSettings integratorSettings(const RenderArgs& a) {
    IntegratorSettings method;
    integratorKindNamed(a.integrator, &method.kind);  // (checked with the arguments)
    method.connect = a.connect;
    method.maxDepth = a.maxDepth;
    method.nextEventEstimation = a.nee;
    method.guiding = a.guiding;
    method.guidingAuto = a.guidingAuto;
    // (Not where the film tracks noise: BdptOptions::partialPilot.)
    method.partialPilot = a.noiseThreshold <= 0 && !a.aovVariance && a.strategyDir.empty();
    method.guidedDistanceDepth = a.guidedDistances;
    method.volumeLights = a.volumeLights;
    method.heuristic = a.heuristic;
    method.plannedPasses = a.seconds > 0 ? 0 : a.spp;
    if (!a.allocation.empty()) allocationNamed(a.allocation, a.connect, &method.allocation);
    method.oneEventSplit = a.strategyDir.empty();
    return method;
}

// The connection shares the render learns (connection_shares.h): the path tracer's, or the
// path tracer's inside bdpt and auto; null if none.
const ConnectionShares* connectionSharesOf(const RenderArgs& a, const Integrator& integrator) {
    if (a.integrator == "pt") return static_cast<const PathTracer&>(integrator).connectionShares();
    return static_cast<const BdptIntegrator&>(integrator).connectionShares();
}

// The bidirectional tracer whose strategies the strategy images show: with auto, the
// allocation it chose; with light tracing's learned share (bdpt; auto in single scattering,
// when its duel kept the allocation that carries it), that share.
BdptOptions strategyOptions(BdptOptions o, const AllocationPlanner* planner, const DirectLightTracing* direct) {
    if (planner) {
        o.allocation = planner->chosen();
        o.efficiencyAware = false;
    }
    if (direct && (!planner || planner->pilotAllocationAt(1 << 30))) o.directLightTracing = direct->factor();
    return o;
}

// What the render did: its line (size, passes, time, speed, dropped samples, memory), auto's
// choice, with --stats the work per sample and the learned share, under mpirun each rank's
// speed and the load balance.
void printSummary(const RenderArgs& a, const RankGroup& group, Resolution res, const Film& film, const RenderStats& stats,
                  uint64_t nonFinite, const AllocationPlanner* planner, const DirectLightTracing* direct,
                  const PathGuide* guide, const DistributedResult& shared, const ConnectionShares* shares) {
    double seconds = stats.seconds > 0 ? stats.seconds : 1e-9;
    std::printf("%s: %dx%d, %d spp, %.3f s, %.0f samples/s, %.0f rays/s, %llu non-finite, peak %.0f MiB\n",
                a.output.c_str(), res.width, res.height, film.passes(), stats.seconds,
                double(stats.samples) / seconds, double(stats.rays) / seconds,
                static_cast<unsigned long long>(nonFinite), peakMemoryMiB());
    if (a.noiseThreshold > 0 && film.tracksNoise() && a.wholeImage) {
        std::printf("%s: estimated relative error %.3g, target %g%s\n", a.defaultRule ? "stopping rule" : "target error",
                    std::sqrt(stats.estimatedRelMse), a.noiseThreshold,
                    stats.activePixels == 0 ? "" : (" (not reached in " + std::to_string(film.passes()) + " passes)").c_str());
    } else if (a.noiseThreshold > 0 && film.tracksNoise()) {
        double mean = 0;
        for (int32_t n : film.sampleCounts()) mean += n;
        mean /= double(film.sampleCounts().size());
        std::printf("adaptive: %.1f spp on average, %d of %d pixels still going on, estimated relative error %.3g "
                    "(threshold %g)\n",
                    mean, stats.activePixels, res.width * res.height, std::sqrt(stats.estimatedRelMse), a.noiseThreshold);
    }
    if (planner) std::printf("%s", (a.stats ? planner->report() : planner->summaryLine() + "\n").c_str());
    if (a.stats && !group.distributed()) std::printf("%s", workPerSample(a.integrator, stats).c_str());  // (counters stay per rank)
    if (a.stats && guide) std::printf("%s", guide->report().text().c_str());
    // (Inside auto and bdpt the shares learn only where the path tracer renders: in auto's duel
    // too, but they are shown only where it chose the path tracer.)
    const bool sharesRender =
        a.integrator == "pt" || (shares && !shares->learning() && (!planner || (planner->decided() && planner->chosen().pathTracer)));
    if (a.stats && shares && sharesRender) std::printf("%s", shares->report().c_str());
    if (direct && a.stats && direct->passes() == DirectLightTracing::kPasses)
        std::printf("light tracing's share of one-scattering paths: factor %.4g (relative variance of a pass alone, summed over pixels: "
                    "camera side %.4g, light tracing %.4g%s)\n",
                    direct->factor(), direct->cameraVariance(), direct->lightVariance(),
                    direct->cameraGain() > 0 ? (", checked with Sobol numbers: gain at 4 passes camera side " +
                                                fixed4(direct->cameraGain()) + ", light tracing " + fixed4(direct->lightGain()))
                                                   .c_str()
                                             : "");
    if (direct && a.stats && direct->costRatio() > 0) {
        const double gain = direct->splitGain();
        std::printf("light tracing %s: with it the one-event paths' variance is %.3g× %s (the check's 4-pass batches, "
                    "carried to the render's length), at %.3g× the cost (counted)\n",
                    direct->off() ? "off" : "kept", gain >= 1 ? gain : 1.0 / gain, gain >= 1 ? "lower" : "higher",
                    direct->costRatio());
    }
    if (group.distributed()) {
        // Per rank: samples/s over its own rendering time; the balance: the least busy rank's
        // rendering time over the busiest one's.
        double lo = 1e300, hi = 0;
        std::string perRank;
        for (size_t r = 0; r < shared.ranks.size(); ++r) {
            const RankReport& rr = shared.ranks[r];
            lo = std::min(lo, rr.busySeconds);
            hi = std::max(hi, rr.busySeconds);
            perRank += (r ? ", " : "") + std::to_string(int(rr.busySeconds > 0 ? rr.samples / rr.busySeconds : 0.0));
        }
        std::printf("ranks: %d; samples/s per rank: %s; load balance %.2f (least over most busy); reduction %.3f s\n",
                    group.size(), perRank.c_str(), hi > 0 ? lo / hi : 1.0, shared.reduceSeconds);
    }
}

int renderOn(const RankGroup& group, const std::vector<std::string>& argv) {
    RenderArgs a;
    if (!parseRenderArgs(argv, a)) return kExitOk;
    const bool lead = group.rank() == 0;
    if (group.distributed() && !a.strategyDir.empty())
        throw UsageError("--strategy-images needs a single process (not mpirun)");
    if (group.distributed() && a.noiseThreshold > 0)
        throw UsageError(a.wholeImage ? "--target-error needs a single process (not mpirun): the image's noise is estimated from the whole film between passes"
                                      : "--noise-threshold needs a single process (not mpirun): pixels are chosen from the whole film between passes");
    if (group.distributed() && a.aovVariance)
        throw UsageError("--aov variance needs a single process (not mpirun): the ranks' films keep no squares");
    // Under a time budget every rank would decide from its own pace: --guiding auto stays off.
    // (With --spp every rank renders the training passes itself, below, as with --guiding on.)
    if (group.distributed() && a.seconds > 0) a.guidingAuto = false;
    try {
        imageFormatFor(a.output);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }

    // Whatever fails on one rank (a file only rank 0 touches) must stop them all: the ranks
    // agree before any collective work.
    std::optional<Checkpoint> resumed;
    std::exception_ptr setupError;
    try {
        if (lead) {
            checkImageWritable(a.output);  // std::runtime_error: exit code 1
            if (!a.checkpoint.empty()) checkCheckpointWritable(a.checkpoint);
            if (!a.resume.empty()) resumed = readCheckpoint(a.resume);  // a bad file fails before the scene loads
        }
    } catch (...) {
        setupError = std::current_exception();
    }
    if (!group.allOk(!setupError)) {
        if (setupError) std::rethrow_exception(setupError);
        return kExitFailure;  // (rank 0 reports it)
    }

    std::optional<Scene> sceneStorage;
    Resolution res;
    if (const int exit = loadAgreedScene(group, argv, a, sceneStorage, res); exit >= 0) return exit;
    const Scene& scene = *sceneStorage;

    // Denoising layers (--aov): computed once, written with every image.
    std::vector<ImageLayer> layers;
    if (lead && (a.aovAlbedo || a.aovNormal)) {
        DenoiseFeatures features = denoiseFeatures(scene, res.width, res.height, a.seed, a.threads);
        if (a.aovAlbedo) layers.push_back({"Albedo", {"R", "G", "B"}, std::move(features.albedo)});
        if (a.aovNormal) layers.push_back({"Normal", {"X", "Y", "Z"}, std::move(features.normal)});
    }
    // The variance layer comes from the film as it is when written.
    auto layersOf = [&](const Film& f) {
        if (!a.aovVariance || !f.tracksNoise()) return layers;
        std::vector<ImageLayer> all = layers;
        all.push_back({"Variance", {"R", "G", "B"}, pixelVariances(f)});
        return all;
    };

    const IntegratorSettings method = integratorSettings(a);
    BdptOptions bdptOptions = brume::bdptOptions(method);  // for the strategy images
    std::unique_ptr<Integrator> integratorPtr = makeIntegrator(method);
    Integrator& integrator = *integratorPtr;

    // Checkpoint state: the settings, the film (possibly resumed) and the non-finite samples
    // dropped by earlier runs.
    const std::string scenePath = absolutePath(a.scene);
    CheckpointSettings settings;
    if (!a.checkpoint.empty() || resumed) settings = checkpointSettings(a, res, scene.desc());
    Film film(res.width, res.height);
    if (a.aovVariance) film.trackNoise();  // (the variance layer reads its squares)
    uint64_t earlierNonFinite = 0;
    // (Only rank 0 reads the checkpoint: the ranks agree on how that went before they wait for
    // its passes and state; a refused checkpoint under mpirun left the other ranks waiting.)
    std::exception_ptr resumeError;
    try {
        if (resumed) {
            checkResumable(a.resume, *resumed, settings, res, a.spp);
            film = std::move(resumed->film);
            try {
                integrator.loadState(resumed->integratorState);
            } catch (const std::exception& e) {
                throw std::runtime_error(a.resume + ": corrupt checkpoint (" + e.what() + ")");
            }
            earlierNonFinite = resumed->nonFinite;
            resumed.reset();
            std::fprintf(stderr, "brume: resuming %s at pass %d of %d\n", a.resume.c_str(), film.passes(), a.spp);
        }
    } catch (...) {
        resumeError = std::current_exception();
    }
    if (const int exit = agreeAfterSetup(group, resumeError); exit >= 0) return exit;
    // Other ranks start from the resumed pass with rank 0's integrator state (auto's planner).
    int donePasses = film.passes();
    if (group.distributed()) {
        donePasses = std::stoi(group.broadcast(std::to_string(donePasses)));
        const std::string state = group.broadcast(lead ? integrator.saveState() : std::string());
        std::exception_ptr stateError;
        try {
            if (!lead) integrator.loadState(state);
        } catch (...) {
            stateError = std::current_exception();
        }
        if (const int exit = agreeAfterSetup(group, stateError); exit >= 0) return exit;
    }

    RenderOptions options;
    options.width = res.width;
    options.height = res.height;
    options.spp = a.spp;
    options.timeBudget = a.seconds;
    // In single scattering a time budget ends on a block of Sobol passes (renderer.h).
    options.sobolBlocks = a.maxDepth >= 0 && a.maxDepth <= 1;
    options.seed = a.seed;
    options.sampler = a.sampler;
    options.threads = a.threads;
    options.progress = ::isatty(2) != 0;
    options.noiseThreshold = a.noiseThreshold;
    options.noiseWholeImage = a.wholeImage;

    // Periodic checkpoints and images (--write-every) between passes; the state and image at
    // the end are written below. A failed periodic write is a warning: the render goes on and
    // the next one may succeed.
    Clock::time_point lastSave = Clock::now(), lastWrite = Clock::now();
    auto periodic = [&](const Film& f, uint64_t nonFiniteSoFar) {
        auto warnOnFailure = [](const std::function<void()>& write) {
            try {
                write();
            } catch (const std::exception& e) {
                std::fprintf(stderr, "brume: warning: %s\n", e.what());
            }
        };
        if (!a.checkpoint.empty() && secondsSince(lastSave) >= a.checkpointEvery) {
            warnOnFailure([&] { writeCheckpoint(a.checkpoint, scenePath, settings, f, nonFiniteSoFar, integrator.saveState()); });
            lastSave = Clock::now();
        }
        if (a.writeEvery > 0 && secondsSince(lastWrite) >= a.writeEvery) {
            warnOnFailure([&] { writeImage(a.output, res.width, res.height, finalImage(f, integrator, a.sampler), layersOf(f)); });
            lastWrite = Clock::now();
        }
    };
    RenderControl control;
    control.cancel = &gInterrupted;
    control.dropInFlight = true;
    control.afterPass = [&](const Film& f, const RenderStats& s) {
        if (s.passes == a.stopAfterPasses) ::raise(SIGTERM);
        if (gInterrupted.load() || (a.seconds <= 0 && f.passes() >= a.spp)) return;  // (the end writes both)
        periodic(f, earlierNonFinite + s.nonFinite);
    };
    catchSignals();  // kept to the end: a signal while the files are written does not cut them short
    if (a.stopAfterPasses == 0) ::raise(SIGTERM);
    RenderStats stats;
    DistributedResult shared;
    if (group.distributed()) {
        PassPlan plan;
        plan.firstPass = donePasses;
        plan.lastPass = a.seconds > 0 ? -1 : a.spp;
        plan.timeBudget = a.seconds;
        plan.failRank = a.failRank;
        plan.failPass = a.failPass;
        // auto decides after its pilot and duel passes: every rank renders them, so all decide alike.
        // So does bdpt its passes that learn light tracing's share (direct_light_tracing.h), and
        // in single scattering, where the split checks that share with Sobol numbers and turns
        // light tracing off where it does not pay, the check's passes.
        const bool learns = a.integrator == "bdpt" && static_cast<const BdptIntegrator&>(integrator).directLightTracing();
        const int checkPasses = learns && static_cast<const BdptIntegrator&>(integrator).checksLightTracing(scene)
                                    ? DirectLightTracing::kCheckPasses
                                    : 0;
        // So do the path tracer and bdpt their guide's training passes (path_guide.h), bdpt's
        // before its passes that learn light tracing's share.
        const int guidePasses = a.guiding ? PathGuide::kLastFitPass : 0;
        // And the path tracer the passes that learn its connection shares (connection_shares.h).
        // (auto's and bdpt's path tracer learn theirs in its 8 duel passes, or the 8 passes
        // after auto's pilot where there is no duel, or from pass 0 with `--allocation "path
        // tracer"`; bdpt's single-scattering split in light tracing's check passes, or in its
        // first 8 passes where light tracing's factor is not learned.)
        const bool learnsShares = connectionSharesOf(a, integrator) != nullptr;
        const int sharePasses = learnsShares ? ConnectionShares::kLearningPasses : 0;
        // And --guiding auto (with --spp: every rank starts the guide at the same pass, after
        // the shares and auto's choice, guide_start.h) the guide's training passes after them,
        // where a guide may start (passes that every rank then renders in vain where none does).
        const bool mayGuide = a.guidingAuto && a.spp >= GuideStart::kAutoPasses && (a.maxDepth < 0 || a.maxDepth >= 2);
        const int autoGuidePasses = mayGuide ? PathGuide::kLastFitPass : 0;
        plan.pilotEnd = bdptOptions.efficiencyAware
                            ? std::max(donePasses, AllocationPlanner::kMaxLastDecisionPass + 1 + sharePasses + autoGuidePasses)
                        : learns    ? std::max(donePasses, guidePasses + DirectLightTracing::kPasses + checkPasses)
                        : a.guiding ? std::max(donePasses, std::max(guidePasses, learnsShares ? ConnectionShares::kLearningPasses : 0))
                        : learnsShares || autoGuidePasses > 0 ? std::max(donePasses, sharePasses + autoGuidePasses)
                                                              : donePasses;
        options.progress = false;
        auto interrupted = [&] {
            if (lead && a.stopAfterPasses > 0 && film.passes() - donePasses >= a.stopAfterPasses) ::raise(SIGTERM);
            return gInterrupted.load();
        };
        // Rank 0 gathers the film at the shorter of the two periods; periodic() writes what is due.
        const double every = std::min(a.checkpoint.empty() ? 1e30 : a.checkpointEvery, a.writeEvery > 0 ? a.writeEvery : 1e30);
        auto save = [&](const Film& f, uint64_t nf) { periodic(f, earlierNonFinite + nf); };
        shared = renderOnRanks(group, scene, integrator, options, film, plan, interrupted, every < 1e30 ? every : 0.0, save);
        stats = shared.stats;
        // A pass that failed on some rank ended the render on every rank: each that failed
        // says why, naming itself; nothing is written.
        if (shared.failed) {
            if (shared.failure) {
                std::fprintf(stderr, "brume: rank %d: %s\n", group.rank(), errorText(shared.failure).c_str());
            } else if (lead) {
                std::fprintf(stderr, "brume: the render failed on another rank; nothing written\n");
            }
            return kExitFailure;
        }
        if (shared.stopped && gSignal.load() == 0) gSignal.store(SIGTERM);  // stopped for another rank
        if (shared.stopped) gInterrupted.store(true);
        if (!lead) return shared.stopped ? exitCodeFor(gSignal.load()) : kExitOk;
    } else if (a.seconds > 0 || film.passes() < a.spp) {
        RenderOptions rest = options;
        rest.spp = a.spp - film.passes();  // ignored with --time
        stats = render(scene, integrator, rest, film, control);
    }
    const uint64_t nonFinite = earlierNonFinite + stats.nonFinite;
    const int sig = gSignal.load();

    if (film.passes() == 0) {
        std::fprintf(stderr, "brume: stopped by %s before the first pass was complete; nothing written\n",
                     signalName(sig));
        return exitCodeFor(sig);
    }
    // The image is written even if the checkpoint cannot be, then the checkpoint's error is
    // reported. A complete render needs no checkpoint any more.
    std::exception_ptr checkpointError;
    // (Adaptive sampling ends a render early once every pixel has stopped.)
    const bool converged = a.noiseThreshold > 0 && !gInterrupted.load() && stats.passes > 0 && stats.activePixels == 0;
    const bool complete = a.seconds > 0 || film.passes() >= a.spp || converged;
    if (!a.checkpoint.empty() && !complete) {
        try {
            writeCheckpoint(a.checkpoint, scenePath, settings, film, nonFinite, integrator.saveState());
        } catch (...) {
            checkpointError = std::current_exception();
        }
    }
    writeImage(a.output, res.width, res.height, finalImage(film, integrator, options.sampler), layersOf(film));
    if (checkpointError) std::rethrow_exception(checkpointError);
    if (!a.checkpoint.empty() && complete) std::remove(a.checkpoint.c_str());
    const AllocationPlanner* planner =
        a.integrator == "auto" ? static_cast<const BdptIntegrator&>(integrator).planner() : nullptr;  // (null: bdpt)
    const DirectLightTracing* direct =
        a.integrator != "pt" ? static_cast<const BdptIntegrator&>(integrator).directLightTracing() : nullptr;
    const PathGuide* guide = a.integrator == "pt" ? static_cast<const PathTracer&>(integrator).guide()
                                                  : static_cast<const BdptIntegrator&>(integrator).guide();
    if (!a.strategyDir.empty() && !gInterrupted.load())
        writeStrategyImages(scene, strategyOptions(bdptOptions, planner, direct), options, a.strategyDir);

    const ConnectionShares* shares = connectionSharesOf(a, integrator);
    printSummary(a, group, res, film, stats, nonFinite, planner, direct, guide, shared, shares);
    std::fflush(stdout);
    if (gInterrupted.load()) {
        std::string done = std::to_string(film.passes()) + (a.seconds > 0 ? "" : " of " + std::to_string(a.spp));
        std::string saved = complete || a.checkpoint.empty() ? "" : ", state in " + a.checkpoint;
        std::fprintf(stderr, "brume: stopped by %s after %s passes (%d spp in %s%s)\n", signalName(sig),
                     done.c_str(), film.passes(), a.output.c_str(), saved.c_str());
        return exitCodeFor(sig);
    }
    return kExitOk;
}

}  // namespace

int runRender(const std::vector<std::string>& argv) {
    RankGroup group;
    if (group.rank() == 0) return renderOn(group, argv);
    // Ranks other than 0 fail quietly: rank 0 reports the same problem.
    try {
        return renderOn(group, argv);
    } catch (const UsageError&) {
        return kExitUsage;
    } catch (...) {
        return kExitFailure;
    }
}

}  // namespace brume::cli
