// The nine light-transport methods the stability suite runs on every scene: the path tracer and
// the bidirectional path tracer, each with the four --connect modes, and the efficiency-aware
// tracer (`brume render`'s default), named as `brume bench` names them (pt:density … bdpt:mis,
// auto).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "brume/integrators/integrator_settings.h"

namespace brume::test {

struct Method {
    bool bdpt = false;
    ConnectMode connect = ConnectMode::Mis;
    bool automatic = false;  // the efficiency-aware tracer (bdpt, --connect mis)

    std::string name() const {
        const char* mode = connect == ConnectMode::Density       ? "density"
                           : connect == ConnectMode::EquiAngular ? "equiangular"
                           : connect == ConnectMode::Product     ? "product"
                                                                 : "mis";
        if (automatic) return "auto";
        return std::string(bdpt ? "bdpt:" : "pt:") + mode;
    }
    std::unique_ptr<Integrator> make(int maxDepth) const {
        IntegratorSettings s;
        s.kind = automatic ? IntegratorKind::EfficiencyAware : bdpt ? IntegratorKind::Bidirectional : IntegratorKind::PathTracer;
        s.connect = connect;
        s.maxDepth = maxDepth;
        return makeIntegrator(s);
    }
};

inline const Method kPtDensity{false, ConnectMode::Density}, kPtEquiAngular{false, ConnectMode::EquiAngular},
    kPtProduct{false, ConnectMode::Product}, kPtMis{false, ConnectMode::Mis}, kBdptDensity{true, ConnectMode::Density},
    kBdptEquiAngular{true, ConnectMode::EquiAngular}, kBdptProduct{true, ConnectMode::Product},
    kBdptMis{true, ConnectMode::Mis}, kAuto{true, ConnectMode::Mis, true};

inline const std::vector<Method>& allMethods() {
    static const std::vector<Method> all{kPtDensity,   kPtEquiAngular,   kPtProduct, kPtMis, kBdptDensity,
                                         kBdptEquiAngular, kBdptProduct, kBdptMis, kAuto};
    return all;
}

}  // namespace brume::test
