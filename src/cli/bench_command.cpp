// brume bench SCENE --out DIR: equal-time comparison of light-transport methods. Every
// method renders the scene from scratch for each time budget (whole passes until the budget
// is spent, one fixed seed); each image is compared with a reference (given, or rendered
// once with pt:mis at many spp and cached in DIR) and the errors, the measured seconds and
// the efficiency 1 / (relMSE · seconds) go to DIR/results.csv and to stdout.
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "brume/cli/build_identity.h"
#include "brume/cli/scene_identity.h"
#include "brume/cli/command_line.h"
#include "brume/cli/commands.h"
#include "brume/integrators/allocation_planner.h"
#include "brume/integrators/bdpt_allocation.h"
#include "brume/integrators/bdpt.h"
#include "brume/integrators/integrator_settings.h"
#include "brume/integrators/path_tracer.h"
#include "brume/film/film.h"
#include "brume/film/image_io.h"
#include "brume/render/fnv1a.h"
#include "brume/render/renderer.h"

namespace brume::cli {

namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------
// The methods. Adding one is adding a line to kMethods.

struct BenchMethod {
    const char* name;
    bool byDefault;  // part of the default --methods list
    const char* what;
    IntegratorSettings settings;  // (without the depth, which the command line gives)
};

// A method with the sampler it renders with; named METHOD, or METHOD:independent.
struct BenchChoice {
    const BenchMethod* method;
    SamplerKind sampler;
    std::string name;
    std::string allocation;  // bdpt@NAME: bdpt:mis with one of auto's candidate allocations
    EmitterSampling emitters = EmitterSampling::SolidAngle;  // METHOD:area: emissive triangles by area
    bool guided = false;  // METHOD:guided: pt or bdpt with path guiding (--guiding on), training included
};

IntegratorSettings pt(ConnectMode connect) {
    IntegratorSettings s;
    s.kind = IntegratorKind::PathTracer;
    s.connect = connect;
    return s;
}

IntegratorSettings bdpt(ConnectMode connect, bool exactEquiAngular = false, bool generalEquiAngular = false,
                        float generalConnection = BdptAllocation{}.generalConnection) {
    IntegratorSettings s;
    s.kind = IntegratorKind::Bidirectional;
    s.connect = connect;
    s.exactEquiAngular = exactEquiAngular;
    s.generalEquiAngular = generalEquiAngular;
    s.allocation.generalConnection = generalConnection;
    return s;
}

// The default of brume render: auto, which starts a guide once it has chosen the path tracer
// where enough passes follow (--guiding auto), with its partial pilot pass. The fixed methods
// render unguided (METHOD:guided: from the first pass).
IntegratorSettings byDefault() {
    IntegratorSettings s;
    s.guidingAuto = true;
    s.partialPilot = true;
    return s;
}

const BenchMethod kMethods[] = {
    {"auto", true, "the efficiency-aware bidirectional tracer (the default of brume render), pilot included",
     byDefault()},
    {"pt:density", true, "path tracer, light connections from the free-flight point", pt(ConnectMode::Density)},
    {"pt:equiangular", true, "path tracer, equi-angular light connections", pt(ConnectMode::EquiAngular)},
    {"pt:product", true, "path tracer, equi-angular x phase light connections (plain equi-angular where g = 0)",
     pt(ConnectMode::Product)},
    {"pt:mis", true, "path tracer, both connections MIS-weighted with phase sampling", pt(ConnectMode::Mis)},
    {"bdpt:density", true, "bidirectional path tracer, free-flight vertices only (plain BDPT)", bdpt(ConnectMode::Density)},
    {"bdpt:equiangular", true, "bidirectional path tracer, equi-angular light connections", bdpt(ConnectMode::EquiAngular)},
    {"bdpt:product", false, "bidirectional path tracer, equi-angular x phase light and camera connections",
     bdpt(ConnectMode::Product)},
    {"bdpt:mis", true, "bidirectional path tracer, both connection variants MIS-weighted", bdpt(ConnectMode::Mis)},
    {"bdpt:mis-exact", false, "bdpt:mis with exact equi-angular densities in the weights (a ray each)",
     bdpt(ConnectMode::Mis, true)},
    {"bdpt:mis-general", false, "bdpt:mis with equi-angular variants of general connections (s, t >= 2) too, all made",
     bdpt(ConnectMode::Mis, false, true, 1.0f)},
    {"bdpt:mis-all", false, "bdpt:mis with every general connection made (s, t >= 2; default: each with probability 1/4)",
     bdpt(ConnectMode::Mis, false, false, 1.0f)},
    {"bdpt:density-all", false, "bdpt:density with every general connection made",
     bdpt(ConnectMode::Density, false, false, 1.0f)},
};

std::unique_ptr<Integrator> makeMethod(const BenchMethod& method, int maxDepth) {
    IntegratorSettings s = method.settings;
    s.maxDepth = maxDepth;
    return makeIntegrator(s);
}

// The integrator of a choice: its method's, or bdpt:mis with a named allocation. With adaptive
// stopping (`adaptive`), unguided where the method guides by --guiding auto, as brume render
// leaves it (a guide started mid-render would learn from passes whose stopped pixels are black),
// and with a whole pilot (the film tracks noise: BdptOptions::partialPilot).
std::unique_ptr<Integrator> makeChoice(const BenchChoice& choice, int maxDepth, bool adaptive = false) {
    if (adaptive && choice.method->settings.guidingAuto && !choice.guided && choice.allocation.empty()) {
        IntegratorSettings s = choice.method->settings;
        s.maxDepth = maxDepth;
        s.guidingAuto = false;
        s.partialPilot = false;
        return makeIntegrator(s);
    }
    if (choice.guided) {
        IntegratorSettings s = choice.method->settings;
        s.maxDepth = maxDepth;
        s.guiding = true;
        return makeIntegrator(s);
    }
    if (choice.allocation.empty()) return makeMethod(*choice.method, maxDepth);
    IntegratorSettings s = bdpt(ConnectMode::Mis);
    s.maxDepth = maxDepth;
    allocationNamed(choice.allocation, ConnectMode::Mis, &s.allocation);
    return makeIntegrator(s);
}

constexpr const char* kReferenceMethod = "pt:mis";
constexpr uint64_t kReferenceSeed = 0x5EED;
constexpr double kRelMseEpsilon = 1e-2;

const BenchMethod* findMethod(const std::string& name) {
    for (const BenchMethod& m : kMethods)
        if (name == m.name) return &m;
    return nullptr;
}

std::string methodNames() {
    std::string names;
    for (const BenchMethod& m : kMethods) names += (names.empty() ? "" : ", ") + std::string(m.name);
    return names;
}

// "pt:mis" → "pt_mis": the method's image file name without extension.
std::string methodFileStem(const std::string& name) {
    std::string stem = name;
    for (char& c : stem)
        if (c == ':' || c == ' ' || c == '@' || c == '=' || c == '+') c = '_';
    return stem;
}

// ---------------------------------------------------------------------------------------
// Arguments

struct BenchArgs {
    std::string scene;
    std::string outDir;
    std::string reference;  // empty: render (or reuse) one
    std::vector<BenchChoice> methods;
    std::vector<double> budgets;
    Resolution res{160, 120};
    uint64_t seed = 1;
    bool seedGiven = false;
    int referenceSpp = 1024;
    bool referenceSppGiven = false;
    int maxDepth = -1;
    const BenchMethod* referenceMethod = nullptr;  // null: pt:mis
    bool chart = true;
    int threads = 0;
    double noiseThreshold = 0;  // > 0: also each method's time to that threshold
};

std::vector<std::string> splitList(const std::string& what, const std::string& text) {
    std::vector<std::string> items;
    size_t start = 0;
    for (;;) {
        size_t comma = text.find(',', start);
        std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (item.empty()) throw UsageError(what + ": empty item in '" + text + "'");
        items.push_back(item);
        if (comma == std::string::npos) return items;
        start = comma + 1;
    }
}

const char* const kBenchDescription =
    "Equal-time comparison of light-transport methods. Each method renders SCENE from\n"
    "scratch for each time budget (whole passes until the budget is spent, fixed seed) and\n"
    "is compared with a reference image r:\n"
    "  rel_mse    = mean over pixels and channels of (x - r)^2 / (r^2 + 0.01)\n"
    "  rmse       = sqrt(mean (x - r)^2)\n"
    "  efficiency = 1 / (rel_mse * seconds), seconds as measured\n"
    "Writes DIR/results.csv (the table also goes to stdout) and each method's image at the\n"
    "largest budget as DIR/<method>.exr (':' becomes '_').";

// The methods, then what Ctrl-C does.
std::string benchFooter() {
    std::string text = "methods:\n";
    for (const BenchMethod& m : kMethods) {
        char line[256];
        std::snprintf(line, sizeof line, "  %-18s %s%s\n", m.name, m.what, m.byDefault ? "" : " (not by default)");
        text += line;
    }
    return text +
           "Every method renders with the sobol sampler; METHOD:independent renders it with independent\n"
           "samples instead (e.g. --methods pt:mis,pt:mis:independent). METHOD:area samples light\n"
           "points on emissive triangles by area, without distances by their solid angle (as\n"
           "--emitter-sampling area; e.g. --methods pt:mis,pt:mis:area). METHOD:guided renders a pt or\n"
           "bdpt method with path guiding (--guiding on), its training passes in the time (e.g.\n"
           "--methods pt:mis,pt:mis:guided).\n"
           "\nCtrl-C stops after the current pass; no results.csv is written (exit code 130).";
}

const BenchMethod* namedMethod(const std::string& what, const std::string& name) {
    const BenchMethod* m = findMethod(name);
    if (!m) throw UsageError(what + ": unknown method '" + name + "' (available: " + methodNames() + ")");
    return m;
}

// A method as --methods names it: METHOD, or METHOD:SAMPLER (sobol, the default, or
// independent), e.g. pt:mis:independent.
BenchChoice namedChoice(const std::string& what, const std::string& item) {
    const std::string guidedSuffix = ":guided";
    if (item.size() > guidedSuffix.size() &&
        item.compare(item.size() - guidedSuffix.size(), guidedSuffix.size(), guidedSuffix) == 0) {
        BenchChoice c = namedChoice(what, item.substr(0, item.size() - guidedSuffix.size()));
        if (c.method->settings.kind == IntegratorKind::EfficiencyAware || !c.allocation.empty())
            throw UsageError(what + ": '" + item + "': path guiding needs a pt or bdpt method");
        c.guided = true;
        c.name += guidedSuffix;
        return c;
    }
    const std::string areaSuffix = ":area";
    if (item.size() > areaSuffix.size() && item.compare(item.size() - areaSuffix.size(), areaSuffix.size(), areaSuffix) == 0) {
        BenchChoice c = namedChoice(what, item.substr(0, item.size() - areaSuffix.size()));
        c.emitters = EmitterSampling::Area;
        c.name += areaSuffix;
        return c;
    }
    if (item.rfind("bdpt@", 0) == 0) {
        BdptAllocation allocation;
        if (!allocationNamed(item.substr(5), ConnectMode::Mis, &allocation))
            throw UsageError(what + ": unknown allocation '" + item.substr(5) + "' (brume render --stats lists them)");
        return BenchChoice{namedMethod(what, "bdpt:mis"), SamplerKind::Sobol, item, allocation.name()};
    }
    for (const char* suffix : {":independent", ":sobol"}) {
        const size_t n = std::strlen(suffix);
        if (item.size() > n && item.compare(item.size() - n, n, suffix) == 0) {
            const BenchMethod* m = namedMethod(what, item.substr(0, item.size() - n));
            const SamplerKind kind = parseSamplerKind(what, suffix + 1);
            return BenchChoice{m, kind, kind == SamplerKind::Sobol ? std::string(m->name) : item, std::string()};
        }
    }
    const BenchMethod* m = namedMethod(what, item);
    return BenchChoice{m, SamplerKind::Sobol, m->name, std::string()};
}

// The command line; false if help was asked for (and printed).
bool parseBenchArgs(const std::vector<std::string>& argv, BenchArgs& a) {
    CLI::App app(kBenchDescription, "brume bench");
    configureCommand(app, "SCENE --out DIR [options]");
    app.footer(benchFooter());
    bool methodsGiven = false, budgetsGiven = false;
    addSceneArgument(app, a.scene);
    addOption(app, "-o,--out", "DIR", "output directory, created if missing (required)", [&](const std::string& v) {
        if (v.empty()) throw UsageError("--out: empty directory name");
        a.outDir = v;
    });
    addOption(app, "--methods", "LIST", "comma-separated methods (default: auto, the four pt and three bdpt modes); see below",
              [&](const std::string& v) {
                  for (const std::string& item : splitList("--methods", v)) {
                      BenchChoice m = namedChoice("--methods", item);
                      for (const BenchChoice& other : a.methods)
                          if (other.name == m.name) throw UsageError("--methods: method '" + item + "' given twice");
                      a.methods.push_back(m);
                  }
                  methodsGiven = true;
              });
    addOption(app, "--noise-threshold", "E",
              "also render each method with adaptive stopping at relative error E (as render --noise-threshold; "
              "for at most 10x the largest budget) and report its time to threshold, relative MSE and "
              "efficiency beside its own at the largest budget (DIR/threshold.csv)",
              [&](const std::string& v) { a.noiseThreshold = parsePositiveNumber("--noise-threshold", v, 1e6); });
    addOption(app, "--budgets", "LIST", "comma-separated time budgets in seconds (default 1,2,4)",
              [&](const std::string& v) {
                  for (const std::string& item : splitList("--budgets", v)) {
                      double seconds = parsePositiveSeconds("--budgets", item, 1e6);
                      if (std::find(a.budgets.begin(), a.budgets.end(), seconds) != a.budgets.end())
                          throw UsageError("--budgets: budget " + item + " given twice");
                      a.budgets.push_back(seconds);
                  }
                  budgetsGiven = true;
              });
    addOption(app, "--reference", "FILE",
              "reference image (.exr or .pfm) of the benchmark's size; without it one is rendered with "
              "pt:mis (seed 24301), cached as DIR/reference.exr + DIR/reference.json and reused while the "
              "scene, the size, the spp, the method and the brume build match",
              [&](const std::string& v) {
                  if (v.empty()) throw UsageError("--reference: empty file name");
                  a.reference = v;
              });
    addOption(app, "--reference-spp", "N", "spp of the rendered reference (default 1024)", [&](const std::string& v) {
        a.referenceSpp = int(parseInteger("--reference-spp", v, 1, 1 << 24));
        a.referenceSppGiven = true;
    });
    addOption(app, "--reference-method", "M",
              "the method that renders the reference (default pt:mis; use a bdpt method where only light "
              "tracing finds the light, e.g. caustics through glass)",
              [&](const std::string& v) { a.referenceMethod = namedMethod("--reference-method", v); });
    app.add_flag_callback("--no-chart", [&] { a.chart = false; },
                          "skip the chart and report page (written otherwise by docs/bench/plot_bench.py with "
                          "Debian's python3-matplotlib)");
    addOption(app, "--res", "WxH", "image size (default 160x120)",
              [&](const std::string& v) { a.res = parseResolution("--res", v); });
    addOption(app, "--seed", "N", "seed of the benchmark renders (default 1)", [&](const std::string& v) {
        a.seed = parseUnsigned64("--seed", v);
        a.seedGiven = true;
    });
    addOption(app, "--max-depth", "N", "most scattering events on a path, for every method and the reference "
              "(default: unlimited; 1 = single scattering)",
              [&](const std::string& v) { a.maxDepth = int(parseInteger("--max-depth", v, -1, 1000000)); });
    addOption(app, "--threads", "N", "worker threads (default: all hardware threads)",
              [&](const std::string& v) { a.threads = int(parseInteger("--threads", v, 1, 1024)); });
    if (!parseCommand(app, argv)) return false;

    if (a.scene.empty()) throw UsageError("bench: no scene file given");
    if (a.outDir.empty()) throw UsageError("bench: no output directory given (--out DIR)");
    if (!methodsGiven)
        for (const BenchMethod& m : kMethods)
            if (m.byDefault) a.methods.push_back(BenchChoice{&m, SamplerKind::Sobol, m.name, std::string()});
    if (!budgetsGiven) a.budgets = {1, 2, 4};
    if (!a.referenceMethod) a.referenceMethod = findMethod(kReferenceMethod);
    if (!a.reference.empty()) {
        if (a.referenceSppGiven) throw UsageError("--reference and --reference-spp exclude each other");
        ImageFormat format;
        try {
            format = imageFormatFor(a.reference);
        } catch (const std::invalid_argument&) {
            format = ImageFormat::Png;
        }
        if (format == ImageFormat::Png)
            throw UsageError("--reference: " + a.reference + ": must be an .exr or .pfm image");
    } else if (a.seed == kReferenceSeed) {
        throw UsageError("--seed: " + std::to_string(a.seed) + " is the seed of the rendered reference; pick another");
    }
    return true;
}

// ---------------------------------------------------------------------------------------
// Files

std::string readTextFile(const std::string& path, bool* ok) {
    std::ifstream in(path, std::ios::binary);
    *ok = bool(in);
    if (!in) return {};
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    *ok = !in.bad();
    return text;
}

// Written beside `path` and renamed into place, like the images.
void writeTextFile(const std::string& path, const std::string& text) {
    std::string tmp = path + ".tmp-" + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (out) out << text;
        out.flush();
        if (!out) {
            int err = errno;
            std::error_code ec;
            fs::remove(tmp, ec);
            throw std::runtime_error(path + ": cannot write: " + std::strerror(err));
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        int err = errno;
        std::error_code ec;
        fs::remove(tmp, ec);
        throw std::runtime_error(path + ": cannot write: " + std::strerror(err));
    }
}

// 16 hex digits.
std::string hex64(uint64_t value) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
    return text;
}

// What a cached reference was rendered from, and by which build of brume (another build may
// render differently): the fields of reference.json. A cache matches when every field does.
// The scene is keyed by the FNV-1a hash of every file it was read from (scene_identity.h), so
// a regenerated scene, buffer or grid at the same path does not reuse a stale reference.
using Record = nlohmann::ordered_json;

Record referenceRecord(const std::string& scenePath, const SceneDescription& scene, Resolution res, int spp,
                       const char* method, int maxDepth) {
    std::error_code ec;
    fs::path absolute = fs::weakly_canonical(fs::absolute(scenePath), ec);
    if (ec) absolute = fs::absolute(scenePath).lexically_normal();
    Record r;
    r["scene"] = absolute.string();
    r["scene_fnv1a64"] = hex64(sceneContentHash(scene));
    r["width"] = res.width;
    r["height"] = res.height;
    r["spp"] = spp;
    r["seed"] = kReferenceSeed;
    r["method"] = method;
    r["max_depth"] = maxDepth;
    r["brume_build_fnv1a64"] = buildIdentity();
    return r;
}

std::string recordText(const Record& record) { return record.dump(2) + "\n"; }

// Why a cached reference does not fit (empty when it does).
std::string cacheMismatch(const std::string& cachedText, const Record& wanted) {
    const Record cached = Record::parse(cachedText, nullptr, false);
    if (cached.is_discarded() || !cached.is_object()) return "reference.json is not a JSON object";
    for (const auto& [key, value] : wanted.items()) {
        if (!cached.contains(key)) return "reference.json has no " + key;
        if (cached[key] != value) {
            if (key == "scene_fnv1a64") return "the scene (a file it reads) changed";
            if (key == "brume_build_fnv1a64") return "made by another build of brume";
            if (key == "width" || key == "height") return "different resolution";
            return "different " + key;
        }
    }
    return {};
}

// ---------------------------------------------------------------------------------------
// Rendering and error

std::atomic<bool> gBenchInterrupted{false};

extern "C" void onBenchInterrupt(int) { gBenchInterrupted.store(true); }

void catchBenchInterrupt() {
    struct sigaction sa {};
    sa.sa_handler = onBenchInterrupt;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, nullptr);
}

// CPU time of the whole process, all threads.
double processCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

struct Metrics {
    double relMse = 0, rmse = 0;
};

Metrics compareImages(const std::vector<float>& image, const std::vector<float>& reference) {
    double rel = 0, squared = 0;
    for (size_t i = 0; i < image.size(); ++i) {
        double r = reference[i];
        double d = double(image[i]) - r;
        rel += d * d / (r * r + kRelMseEpsilon);
        squared += d * d;
    }
    double n = double(std::max<size_t>(image.size(), 1));
    return {rel / n, std::sqrt(squared / n)};
}

struct Row {
    const BenchChoice* method;
    double budget;
    double seconds;
    int spp;
    Metrics error;
    double efficiency;
};

std::string csvField(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

std::string format(const char* fmt, double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char text[64];
    std::snprintf(text, sizeof text, fmt, v);
    return text;
}

std::string budgetList(const std::vector<double>& budgets) {
    std::string text;
    for (double b : budgets) text += (text.empty() ? "" : ",") + format("%g", b);
    return text;
}

std::vector<float> readReferenceFile(const std::string& path, Resolution res) {
    int w = 0, h = 0;
    std::vector<float> rgb = readImage(path, &w, &h);
    if (w != res.width || h != res.height)
        throw std::runtime_error(path + ": reference is " + std::to_string(w) + "x" + std::to_string(h) +
                                 ", the benchmark renders " + std::to_string(res.width) + "x" +
                                 std::to_string(res.height) + " (pass --res " + std::to_string(w) + "x" +
                                 std::to_string(h) + ")");
    for (float v : rgb)
        if (!std::isfinite(v)) throw std::runtime_error(path + ": reference has non-finite pixels");
    return rgb;
}

// The chart (DIR/chart.png, .svg) and report page (DIR/report.html), drawn by the plotting
// script next to the sources with Debian's Python; a missing Python module is reported, not
// an error: the numbers are in results.csv.
void writeChart(const std::string& dir) {
    const char* python = "/usr/bin/python3";
    if (::access(python, X_OK) != 0 || ::access(BRUME_PLOT_SCRIPT, R_OK) != 0) {
        std::printf("chart: skipped (needs %s and %s)\n", python, BRUME_PLOT_SCRIPT);
        return;
    }
    std::fflush(stdout);
    pid_t pid = ::fork();
    if (pid == 0) {
        ::execl(python, python, BRUME_PLOT_SCRIPT, dir.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    int status = 0;
    if (pid < 0 || ::waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        std::printf("chart: not written (the plotting script failed; Debian: apt install python3-matplotlib "
                    "python3-numpy python3-openimageio)\n");
}

}  // namespace

// Whether an interrupt came (said once, on stderr).
bool benchInterrupted() {
    if (!gBenchInterrupted.load()) return false;
    std::fputs("brume: interrupted; no results.csv written\n", stderr);
    return true;
}

// The reference a bench compares with, unless one is given: reference.exr in the output
// directory if reference.json says it was rendered for this scene, resolution, depth and build,
// else rendered (and cached) now. False if interrupted.
bool cachedOrRenderedReference(const BenchArgs& a, Scene& scene, Resolution res, const std::string& referencePath,
                               const std::string& recordPath, std::vector<float>& reference) {
    Record wanted = referenceRecord(a.scene, scene.desc(), res, a.referenceSpp, a.referenceMethod->name, a.maxDepth);
    bool haveRecord = false;
    std::string cachedText = readTextFile(recordPath, &haveRecord);
    std::string why = haveRecord ? cacheMismatch(cachedText, wanted) : "no cached reference";
    if (why.empty()) {
        try {
            reference = readReferenceFile(referencePath, res);
        } catch (const std::runtime_error&) {
            why = "cached reference.exr unreadable";
        }
    }
    char what[128];
    std::snprintf(what, sizeof what, "%s, %d spp, seed %llu", a.referenceMethod->name, a.referenceSpp,
                  static_cast<unsigned long long>(kReferenceSeed));
    if (why.empty()) {
        std::printf("reference: reused %s (%s)\n", referencePath.c_str(), what);
    } else {
        std::printf("reference: rendering %s (%s; %s) ...\n", referencePath.c_str(), what, why.c_str());
        std::fflush(stdout);
        std::error_code ec;
        fs::remove(recordPath, ec);  // never a record beside an image it does not describe
        std::unique_ptr<Integrator> integrator = makeMethod(*a.referenceMethod, a.maxDepth);
        RenderOptions options;
        options.width = res.width;
        options.height = res.height;
        options.spp = a.referenceSpp;
        options.seed = kReferenceSeed;
        options.threads = a.threads;
        options.progress = ::isatty(2) != 0;
        scene.setEmitterSampling(EmitterSampling::SolidAngle);
        Film film(res.width, res.height);
        RenderStats stats = render(scene, *integrator, options, film, &gBenchInterrupted);
        if (benchInterrupted()) return false;
        reference = finalImage(film, *integrator, options.sampler);
        writeImage(referencePath, res.width, res.height, reference);
        writeTextFile(recordPath, recordText(wanted));
        std::printf("reference: rendered in %.2f s, cached in %s\n", stats.seconds, recordPath.c_str());
    }
    return true;
}

// results.csv, and the table of efficiencies relative to the first method, per budget.
void writeResults(const std::string& csvPath, const std::string& sceneLabel, const std::vector<Row>& rows,
                  const std::vector<BenchChoice>& methods, const std::vector<double>& budgets, int mw) {
    std::string csv = "scene,method,budget_s,seconds,spp,rel_mse,rmse,efficiency\n";
    for (const Row& r : rows)
        csv += csvField(sceneLabel) + "," + r.method->name + "," + format("%g", r.budget) + "," +
               format("%.6f", r.seconds) + "," + std::to_string(r.spp) + "," + format("%.6e", r.error.relMse) + "," +
               format("%.6e", r.error.rmse) + "," + format("%.6g", r.efficiency) + "\n";
    writeTextFile(csvPath, csv);

    // Efficiency relative to the first method, per budget.
    std::printf("\nefficiency relative to %s (higher is better):\n", methods.front().name.c_str());
    std::printf("%8s", "budget_s");
    for (const BenchChoice& m : methods) std::printf("  %*s", std::max(mw, 8), m.name.c_str());
    std::printf("\n");
    for (size_t b = 0; b < budgets.size(); ++b) {
        std::printf("%8s", format("%g", budgets[b]).c_str());
        const size_t n = methods.size();
        double base = rows[b * n].efficiency;
        for (size_t i = 0; i < n; ++i)
            std::printf("  %*s", std::max(mw, 8), format("%.3f", rows[b * n + i].efficiency / base).c_str());
        std::printf("\n");
    }
}

// Each method again, from scratch, with adaptive stopping at a.noiseThreshold (renderer.h):
// the seconds until every pixel reached it (or 10x the largest budget), the mean spp, the
// estimated and the measured relative MSE, the efficiency, and that over the method's own
// at the largest budget (under relMSE ∝ 1/time, how much sooner it reaches the same error).
// To stdout and `csvPath`. False if interrupted.
bool timeToThreshold(const BenchArgs& a, Scene& scene, const std::vector<float>& reference, const std::vector<Row>& rows,
                     double largest, const std::string& csvPath) {
    std::printf("\ntime to noise threshold %g (adaptive stopping; 'vs uniform': its efficiency over the method's own at %g s):\n",
                a.noiseThreshold, largest);
    std::printf("%-22s  %8s  %8s  %11s  %11s  %11s  %10s\n", "method", "seconds", "mean_spp", "est_rel_mse", "rel_mse",
                "efficiency", "vs_uniform");
    std::string csv = "scene,method,threshold,seconds,mean_spp,converged,estimated_rel_mse,rel_mse,efficiency,vs_uniform\n";
    for (const BenchChoice& choice : a.methods) {
        std::unique_ptr<Integrator> integrator = makeChoice(choice, a.maxDepth, true);
        RenderOptions options;
        options.width = a.res.width;
        options.height = a.res.height;
        options.timeBudget = 10 * largest;
        options.noiseThreshold = a.noiseThreshold;
        options.seed = a.seed;
        options.sampler = choice.sampler;
        options.threads = a.threads;
        scene.setEmitterSampling(choice.emitters);
        Film film(a.res.width, a.res.height);
        RenderStats stats = render(scene, *integrator, options, film, &gBenchInterrupted);
        if (benchInterrupted()) return false;
        double meanSpp = 0;
        for (int32_t n : film.sampleCounts()) meanSpp += n;
        meanSpp /= double(film.sampleCounts().size());
        const Metrics error = compareImages(finalImage(film, *integrator, options.sampler), reference);
        const double efficiency = error.relMse * stats.seconds > 0 ? 1 / (error.relMse * stats.seconds) : HUGE_VAL;
        double uniform = 0;
        for (const Row& r : rows)
            if (r.method == &choice && r.budget == largest) uniform = r.efficiency;
        const double ratio = uniform > 0 ? efficiency / uniform : 0;
        std::printf("%-22s  %8.3f  %8.1f  %11.4e  %11.4e  %11s  %10s%s\n", choice.name.c_str(), stats.seconds, meanSpp,
                    stats.estimatedRelMse, error.relMse, format("%.4g", efficiency).c_str(), format("%.3f", ratio).c_str(),
                    stats.activePixels > 0 ? "  (time limit: not every pixel reached it)" : "");
        std::fflush(stdout);
        csv += csvField(fs::path(a.scene).stem().string()) + "," + choice.name + "," + format("%g", a.noiseThreshold) + "," +
               format("%.6f", stats.seconds) + "," + format("%.3f", meanSpp) + "," + (stats.activePixels == 0 ? "1" : "0") +
               "," + format("%.6e", stats.estimatedRelMse) + "," + format("%.6e", error.relMse) + "," +
               format("%.6g", efficiency) + "," + format("%.4f", ratio) + "\n";
    }
    writeTextFile(csvPath, csv);
    return true;
}

int runBench(const std::vector<std::string>& argv) {
    BenchArgs a;
    if (!parseBenchArgs(argv, a)) return kExitOk;

    // Everything that can fail is checked before the first render.
    Scene scene(loadSceneDescription(a.scene));
    const Resolution res = a.res;
    std::vector<float> reference;
    if (!a.reference.empty()) reference = readReferenceFile(a.reference, res);

    const fs::path dir(a.outDir);
    {
        std::error_code ec;
        if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
            throw std::runtime_error(a.outDir + ": exists and is not a directory");
        fs::create_directories(dir, ec);
        if (ec) throw std::runtime_error(a.outDir + ": cannot create directory: " + ec.message());
    }
    const std::string referencePath = (dir / "reference.exr").string();
    const std::string recordPath = (dir / "reference.json").string();
    const std::string csvPath = (dir / "results.csv").string();
    checkImageWritable(referencePath);

    const int threads = a.threads > 0 ? a.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    const std::string sceneLabel = fs::path(a.scene).stem().string();
    std::printf("brume bench: %s, %dx%d, budgets %s s, seed %llu, %d threads\n", a.scene.c_str(), res.width,
                res.height, budgetList(a.budgets).c_str(), static_cast<unsigned long long>(a.seed), threads);
    std::fflush(stdout);

    catchBenchInterrupt();

    // The reference.
    if (!a.reference.empty()) std::printf("reference: %s (given)\n", a.reference.c_str());
    else if (!cachedOrRenderedReference(a, scene, res, referencePath, recordPath, reference)) return kExitInterrupted;
    std::printf("error: rel_mse = mean over pixels and channels of (x - r)^2 / (r^2 + 0.01); "
                "rmse = sqrt(mean (x - r)^2); efficiency = 1 / (rel_mse * seconds)\n\n");

    // The table, printed row by row as the renders finish. Budgets outermost, so that the
    // methods of one budget run close together in time (and under similar machine load).
    size_t methodWidth = 6, sceneWidth = std::max<size_t>(5, sceneLabel.size());
    for (const BenchChoice& m : a.methods) methodWidth = std::max(methodWidth, m.name.size());
    const int mw = int(methodWidth), sw = int(sceneWidth);
    std::printf("%-*s  %-*s  %8s  %8s  %6s  %11s  %11s  %11s\n", sw, "scene", mw, "method", "budget_s", "seconds",
                "spp", "rel_mse", "rmse", "efficiency");
    std::fflush(stdout);

    const double largest = *std::max_element(a.budgets.begin(), a.budgets.end());
    std::vector<Row> rows;
    std::vector<std::string> imagesWritten;
    for (double budget : a.budgets) {
        for (const BenchChoice& choice : a.methods) {
            const BenchChoice* method = &choice;
            std::unique_ptr<Integrator> integrator = makeChoice(choice, a.maxDepth);
            RenderOptions options;
            options.width = res.width;
            options.height = res.height;
            options.timeBudget = budget;
            options.sobolBlocks = a.maxDepth >= 0 && a.maxDepth <= 1;  // (as render's)
            options.seed = a.seed;
            options.sampler = choice.sampler;
            options.threads = a.threads;
            scene.setEmitterSampling(choice.emitters);
            Film film(res.width, res.height);
            const double cpuBefore = processCpuSeconds();
            RenderStats stats = render(scene, *integrator, options, film, &gBenchInterrupted);
            const double cpu = processCpuSeconds() - cpuBefore;
            if (benchInterrupted()) return kExitInterrupted;
            // Equal-time comparisons assume the threads had the machine to themselves.
            // (More threads than cores or than 16x16 tiles cannot all be busy.)
            const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
            const int workers = std::min({threads, cores, ((res.width + 15) / 16) * ((res.height + 15) / 16)});
            const double busy = cpu / (std::max(stats.seconds, 1e-9) * workers);
            if (busy < 0.8)
                std::fprintf(stderr,
                             "brume: warning: %s at %g s: the %d threads were busy only %.0f%% of the time; "
                             "is the machine loaded? its timing is unreliable\n",
                             method->name.c_str(), budget, workers, 100 * busy);
            std::vector<float> image = finalImage(film, *integrator, options.sampler);
            Row row{method, budget, stats.seconds, stats.passes, compareImages(image, reference), 0};
            double cost = row.error.relMse * row.seconds;
            row.efficiency = cost > 0 ? 1 / cost : HUGE_VAL;
            rows.push_back(row);
            std::printf("%-*s  %-*s  %8s  %8.3f  %6d  %11.4e  %11.4e  %11s\n", sw, sceneLabel.c_str(), mw,
                        method->name.c_str(), format("%g", budget).c_str(), row.seconds, row.spp, row.error.relMse,
                        row.error.rmse, format("%.4g", row.efficiency).c_str());
            // The efficiency-aware tracer's choice, on a line of its own (CSV columns stay as they are).
            if (const auto* bdpt = dynamic_cast<const BdptIntegrator*>(integrator.get()))
                if (const AllocationPlanner* planner = bdpt->planner())
                    std::printf("%-*s  %-*s  %8s  %s\n", sw, "", mw, "", "", planner->summaryLine().c_str());
            std::fflush(stdout);
            if (budget == largest) {
                std::string path = (dir / (methodFileStem(method->name) + ".exr")).string();
                writeImage(path, res.width, res.height, image);
                imagesWritten.push_back(path);
            }
        }
    }

    if (a.noiseThreshold > 0 && !timeToThreshold(a, scene, reference, rows, largest, (dir / "threshold.csv").string()))
        return kExitInterrupted;

    writeResults(csvPath, sceneLabel, rows, a.methods, a.budgets, mw);
    std::printf("\nwrote %s", csvPath.c_str());
    for (const std::string& p : imagesWritten) std::printf(", %s", p.c_str());
    std::printf("\n");
    std::fflush(stdout);
    signal(SIGINT, SIG_DFL);
    if (a.chart) writeChart(a.outDir);
    return kExitOk;
}

}  // namespace brume::cli
