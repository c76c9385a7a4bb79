// misPerCountLanes, which weighs a path under the planner's fourteen settings at once
// (allocation_statistics.cpp), against misWeight under each setting alone: the same bits, on
// every strategy of every path a bidirectional render weighs. Grey and coloured fog, area,
// point and spot lights, several lights picked by where a connection starts, specular chains,
// and a --max-depth whose last event the camera walk passes through (the passed prefix).
#include <catch2/catch.hpp>

#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include "brume/integrators/bdpt.h"
#include "brume/integrators/bdpt_mis.h"
#include "support/film_estimates.h"

using namespace brume;
using namespace brume::test;

namespace {

constexpr int kW = 8;

struct LaneCheck : BdptObserver {
    const Scene* scene = nullptr;
    int passFrom = 1 << 30, passFirstAt = 1 << 30;
    mutable std::mutex mutex;
    mutable long paths = 0, differing = 0, passed = 0;
    mutable std::string first;

    // The planner's settings: seven switches of the allocation (allocation_statistics.cpp),
    // under the power heuristic and its cube, or the balance heuristic alone (seven lanes).
    static int settings(const MisSettings& base, bool power, MisSettings* st) {
        const int sets = power ? 2 : 1;
        for (int k = 0; k < sets; ++k)
            for (int b = 0; b < 7; ++b) {
                MisSettings& x = st[k * 7 + b];
                x = base;
                x.heuristic = !power ? MisHeuristic::Balance : k == 0 ? MisHeuristic::Power : MisHeuristic::Cube;
                x.generalConnection = b == 4 ? 1.0 : 0.0;
                x.cameraConnection = b == 2 || b == 3 || b == 6 ? 1.0 : 0.0;
                x.equiAngularLight = b == 1 || b == 5;
                x.equiAngularCamera = b == 3 || b == 6;
                x.equiAngularOnly = b >= 5;
            }
        return sets * 7;
    }

    void onWeight(const PathVertex* light, int s, const PathVertex* camera, int t, float, bool equiAngular,
                  int hero) const override {
        MisSettings base;
        base.connect = ConnectMode::Mis;
        base.width = base.height = kW;
        base.channels = scene->mediumChannels();
        base.hero = hero;
        base.passFrom = passFrom;
        base.passFirstAt = passFirstAt;
        for (bool power : {true, false}) {
            MisSettings st[kMaxMisLanes];
            const int lanes = settings(base, power, st);
            std::vector<PathVertex> cam(camera, camera + t), lig(light, light + s);
            std::vector<MisSums> cameraSums(size_t(lanes * t)), lightSums(size_t(lanes * s) + 1);
            double alone[kMaxMisLanes], together[kMaxMisLanes];
            for (int l = 0; l < lanes; ++l) {
                misPrefixes(*scene, cam.data(), t, true, st[l]);
                misPrefixes(*scene, lig.data(), s, false, st[l]);
                copyMisSums(cam.data(), t, cameraSums.data() + l * t);
                copyMisSums(lig.data(), s, lightSums.data() + l * s);
                misWeight(*scene, lig.data(), cam.data(), s, t, st[l], equiAngular, false, 0.0, &alone[l]);
            }
            misPerCountLanes(*scene, lig.data(), cam.data(), s, t, st, lanes, equiAngular, false, 0.0, cameraSums.data(), t,
                             lightSums.data(), s, together);
            std::lock_guard<std::mutex> lock(mutex);
            ++paths;
            if (s >= 3 && s + t - 1 >= passFrom) ++passed;
            for (int l = 0; l < lanes; ++l)
                if (std::memcmp(&alone[l], &together[l], sizeof(double)) != 0) {
                    ++differing;
                    if (first.empty())
                        first = "s=" + std::to_string(s) + " t=" + std::to_string(t) + " lane " + std::to_string(l) + ": " +
                                std::to_string(alone[l]) + " alone, " + std::to_string(together[l]) + " in lanes";
                }
        }
    }
};

void checkLanes(const char* file, int spp, int maxDepth = 4, bool passes = false) {
    auto scene = loadTestScene(file);
    LaneCheck check;
    check.scene = scene.get();
    BdptOptions opt{maxDepth, MisHeuristic::Power};
    opt.connect = ConnectMode::Mis;
    opt.hooks.observer = &check;
    if (passes) {  // the walk's indices as --max-depth m sets them (MisSettings::passFrom)
        check.passFrom = maxDepth + 1;
        check.passFirstAt = maxDepth;
    }
    Film film(kW, kW);
    RenderOptions o;
    o.width = o.height = kW;
    o.spp = spp;
    o.seed = 5;
    BdptIntegrator integrator(opt);
    render(*scene, integrator, o, film);
    INFO(file << ": " << check.paths << " weighted paths, " << check.differing << " lanes differing (" << check.first
              << "), " << check.passed << " with the passed prefix");
    CHECK(check.paths > 100);
    CHECK(check.differing == 0);
    if (passes) CHECK(check.passed > 10);
}

}  // namespace

TEST_CASE("MIS weights in lanes are misWeight's under each setting, bit for bit", "[bdpt][mis]") {
    checkLanes("quad_light_fog.gltf", 4);
    checkLanes("quad_light_fog_chromatic.gltf", 4);  // coloured: long double sums over channels
    checkLanes("single_near.gltf", 4);
    checkLanes("many_lights.gltf", 4);              // picks by where a connection starts
    checkLanes("bdpt_glass_sphere.gltf", 4);        // specular chains, a spot light
    checkLanes("quad_light_fog.gltf", 8, 3, true);  // the passed prefix past the last event
}
