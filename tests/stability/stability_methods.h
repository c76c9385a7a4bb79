// The six light-transport methods the stability suite runs on every scene: the path tracer and
// the bidirectional path tracer, each with the three --connect modes, named as `brume bench`
// names them (pt:density … bdpt:mis).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "brume/integrators/bdpt.h"
#include "brume/integrators/path_tracer.h"

namespace brume::test {

struct Method {
    bool bdpt = false;
    ConnectMode connect = ConnectMode::Mis;

    std::string name() const {
        const char* mode = connect == ConnectMode::Density       ? "density"
                           : connect == ConnectMode::EquiAngular ? "equiangular"
                                                                 : "mis";
        return std::string(bdpt ? "bdpt:" : "pt:") + mode;
    }
    std::unique_ptr<Integrator> make(int maxDepth) const {
        if (!bdpt) return std::make_unique<PathTracer>(PathTracerOptions{maxDepth, true, connect});
        BdptOptions o{maxDepth, MisHeuristic::Power};
        o.connect = connect;
        return std::make_unique<BdptIntegrator>(o);
    }
};

inline const Method kPtDensity{false, ConnectMode::Density}, kPtEquiAngular{false, ConnectMode::EquiAngular},
    kPtMis{false, ConnectMode::Mis}, kBdptDensity{true, ConnectMode::Density},
    kBdptEquiAngular{true, ConnectMode::EquiAngular}, kBdptMis{true, ConnectMode::Mis};

inline const std::vector<Method>& allMethods() {
    static const std::vector<Method> all{kPtDensity, kPtEquiAngular, kPtMis, kBdptDensity, kBdptEquiAngular, kBdptMis};
    return all;
}

}  // namespace brume::test
