// brume render SCENE -o OUT [options]: everything is checked before the first sample, the
// image is written in one piece at the end, and a summary line goes to stdout.
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "brume/cli/commands.h"
#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"
#include "brume/render/film.h"
#include "brume/render/image_io.h"
#include "brume/render/renderer.h"

namespace brume::cli {

const char* const kRenderUsage =
    "usage: brume render SCENE -o OUT [options]\n"
    "\n"
    "Renders a glTF scene and writes OUT (.exr: float linear RGB, .pfm: float linear RGB,\n"
    ".png: 8-bit sRGB).\n"
    "\n"
    "options:\n"
    "  -o, --output OUT     output image (required)\n"
    "  --integrator NAME    pt (volumetric path tracer; the default) or bdpt\n"
    "                       (bidirectional path tracer)\n"
    "  --mis HEURISTIC      bdpt: power (the default) or balance\n"
    "  --strategy-images DIR  bdpt: also write DIR/s<S>_t<T>.exr, each strategy's weighted\n"
    "                       contribution (they add up to the image; one extra render each,\n"
    "                       for s + t - 2 up to min(max-depth, 5))\n"
    "  --spp N              samples per pixel (default 16)\n"
    "  --time SECONDS       render whole passes until SECONDS are spent instead of --spp\n"
    "  --max-depth N        most scattering events per path (default -1: unlimited)\n"
    "  --no-nee             no next-event estimation (BSDF/phase sampling only)\n"
    "  --connect MODE       light connections on medium segments: density (from the\n"
    "                       free-flight point), equiangular, or mis (both; the default);\n"
    "                       for bdpt: equi-angular variants of connection vertices\n"
    "  --res WxH            image size (default 640 wide, height from the camera's aspect\n"
    "                       ratio, 640x480 without one)\n"
    "  --seed N             random seed (default 0); the same seed gives the same image\n"
    "                       for any thread count\n"
    "  --threads N          worker threads (default: all hardware threads)\n"
    "  -h, --help           this text\n"
    "\n"
    "Ctrl-C stops after the current pass and writes the image so far (exit code 130).\n";

namespace {

struct RenderArgs {
    std::string scene;
    std::string output;
    std::string integrator = "pt";
    int spp = 16;
    bool sppGiven = false;
    double seconds = 0;
    int maxDepth = -1;
    bool nee = true;
    ConnectMode connect = ConnectMode::Mis;
    MisHeuristic heuristic = MisHeuristic::Power;
    std::string strategyDir;
    Resolution res;  // width 0: from the camera
    uint64_t seed = 0;
    int threads = 0;
    bool help = false;
};

RenderArgs parseRenderArgs(const std::vector<std::string>& argv) {
    RenderArgs a;
    ArgScanner args(argv);
    while (args.next()) {
        const std::string& name = args.current();
        if (!args.isOption()) {
            if (!a.scene.empty()) throw UsageError("more than one scene given ('" + a.scene + "', '" + name + "')");
            a.scene = name;
        } else if (name == "-h" || name == "--help") {
            a.help = true;
        } else if (name == "-o" || name == "--output") {
            a.output = args.value();
            if (a.output.empty()) throw UsageError(name + ": empty file name");
        } else if (name == "--integrator") {
            a.integrator = args.value();
        } else if (name == "--spp") {
            a.spp = int(parseInteger(name, args.value(), 1, 1 << 24));
            a.sppGiven = true;
        } else if (name == "--time") {
            a.seconds = parsePositiveSeconds(name, args.value(), 1e7);
        } else if (name == "--max-depth") {
            a.maxDepth = int(parseInteger(name, args.value(), -1, 1000000));
        } else if (name == "--no-nee") {
            args.noValue();
            a.nee = false;
        } else if (name == "--strategy-images") {
            a.strategyDir = args.value();
        } else if (name == "--mis") {
            std::string h = args.value();
            if (h == "power") a.heuristic = MisHeuristic::Power;
            else if (h == "balance") a.heuristic = MisHeuristic::Balance;
            else throw UsageError("--mis: unknown heuristic '" + h + "' (power or balance)");
        } else if (name == "--connect") {
            std::string mode = args.value();
            if (mode == "density") a.connect = ConnectMode::Density;
            else if (mode == "equiangular") a.connect = ConnectMode::EquiAngular;
            else if (mode == "mis") a.connect = ConnectMode::Mis;
            else throw UsageError("--connect: unknown mode '" + mode + "' (density, equiangular or mis)");
        } else if (name == "--res") {
            a.res = parseResolution(name, args.value());
        } else if (name == "--seed") {
            a.seed = parseUnsigned64(name, args.value());
        } else if (name == "--threads") {
            a.threads = int(parseInteger(name, args.value(), 1, 1024));
        } else {
            args.unknown();
        }
    }
    if (a.help) return a;
    if (a.scene.empty()) throw UsageError("render: no scene file given");
    if (a.output.empty()) throw UsageError("render: no output file given (-o OUT)");
    if (a.integrator != "pt" && a.integrator != "bdpt")
        throw UsageError("unknown integrator '" + a.integrator + "' (available: pt, bdpt)");
    if (a.sppGiven && a.seconds > 0) throw UsageError("--spp and --time exclude each other");
    if (!a.strategyDir.empty() && a.integrator != "bdpt") throw UsageError("--strategy-images needs --integrator bdpt");
    if (!a.strategyDir.empty() && a.seconds > 0) throw UsageError("--strategy-images needs --spp, not --time");
    return a;
}

std::atomic<bool> gInterrupted{false};

// One render per strategy (s, t), same seed and spp, each keeping only that strategy's
// weighted contribution: the images add up to the full render.
void writeStrategyImages(const Scene& scene, BdptOptions bdpt, RenderOptions options, const std::string& dir) {
    ::mkdir(dir.c_str(), 0777);
    const int maxDepth = bdpt.maxDepth < 0 ? 5 : std::min(bdpt.maxDepth, 5);
    options.progress = false;
    bdpt.weighted = true;
    for (int depth = 0; depth <= maxDepth; ++depth)
        for (int s = 0; s <= depth + 2; ++s) {
            int t = depth + 2 - s;
            if (t < 1) continue;
            bdpt.onlyS = s;
            bdpt.onlyT = t;
            BdptIntegrator integrator(bdpt);
            Film film(options.width, options.height);
            render(scene, integrator, options, film, &gInterrupted);
            if (gInterrupted.load()) return;
            std::string path = dir + "/s" + std::to_string(s) + "_t" + std::to_string(t) + ".exr";
            writeImage(path, options.width, options.height, film.rgb());
        }
    std::printf("strategy images in %s\n", dir.c_str());
}

extern "C" void onInterrupt(int) { gInterrupted.store(true); }

// The first Ctrl-C asks the renderer to stop after the current pass; SA_RESETHAND makes a
// second one kill the process as usual.
void catchInterrupt() {
    struct sigaction sa {};
    sa.sa_handler = onInterrupt;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, nullptr);
}

}  // namespace

int runRender(const std::vector<std::string>& argv) {
    RenderArgs a = parseRenderArgs(argv);
    if (a.help) {
        std::fputs(kRenderUsage, stdout);
        return kExitOk;
    }
    try {
        imageFormatFor(a.output);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    checkImageWritable(a.output);  // std::runtime_error: exit code 1

    SceneDescription desc = loadSceneDescription(a.scene);
    Resolution res = imageResolution(desc.camera, a.res);
    Scene scene(std::move(desc));

    PathTracerOptions ptOptions;
    ptOptions.maxDepth = a.maxDepth;
    ptOptions.nextEventEstimation = a.nee;
    ptOptions.connect = a.connect;
    BdptOptions bdptOptions;
    bdptOptions.maxDepth = a.maxDepth;
    bdptOptions.heuristic = a.heuristic;
    bdptOptions.connect = a.connect;
    std::unique_ptr<Integrator> integratorPtr;
    if (a.integrator == "bdpt") integratorPtr = std::make_unique<BdptIntegrator>(bdptOptions);
    else integratorPtr = std::make_unique<PathTracer>(ptOptions);
    const Integrator& integrator = *integratorPtr;

    RenderOptions options;
    options.width = res.width;
    options.height = res.height;
    options.spp = a.spp;
    options.timeBudget = a.seconds;
    options.seed = a.seed;
    options.threads = a.threads;
    options.progress = ::isatty(2) != 0;

    Film film(res.width, res.height);
    catchInterrupt();
    RenderStats stats = render(scene, integrator, options, film, &gInterrupted);
    signal(SIGINT, SIG_DFL);

    writeImage(a.output, res.width, res.height, film.rgb());
    if (!a.strategyDir.empty() && !gInterrupted.load()) writeStrategyImages(scene, bdptOptions, options, a.strategyDir);

    double seconds = stats.seconds > 0 ? stats.seconds : 1e-9;
    std::printf("%s: %dx%d, %d spp, %.3f s, %.0f samples/s, %.0f rays/s, %llu non-finite\n", a.output.c_str(),
                res.width, res.height, stats.passes, stats.seconds, double(stats.samples) / seconds,
                double(stats.rays) / seconds, static_cast<unsigned long long>(stats.nonFinite));
    std::fflush(stdout);
    if (gInterrupted.load()) {
        std::fprintf(stderr, "brume: interrupted after %d passes\n", stats.passes);
        return kExitInterrupted;
    }
    return kExitOk;
}

}  // namespace brume::cli
