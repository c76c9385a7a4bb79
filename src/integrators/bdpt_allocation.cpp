#include "brume/integrators/bdpt_allocation.h"

#include <cstdio>

namespace brume {

std::string BdptAllocation::name() const {
    std::string ea = std::string(equiAngularLight ? "L" : "") + (lightSubpaths && lightTracing && equiAngularCamera ? "C" : "");
    if (pathTracer) return "path tracer";
    if (!lightSubpaths) return equiAngularLight ? (equiAngularOnly ? "pt ea-only" : "pt+ea") : "pt";
    char p[16];
    std::snprintf(p, sizeof p, "%g", double(generalConnection));
    return std::string("bdpt") + (lightTracing ? " lt" : "") + " p=" + p + (ea.empty() ? "" : (equiAngularOnly ? " ea-only=" : " ea=") + ea);
}

bool BdptAllocation::operator==(const BdptAllocation& o) const {
    return lightSubpaths == o.lightSubpaths && lightTracing == o.lightTracing && generalConnection == o.generalConnection &&
           equiAngularLight == o.equiAngularLight && equiAngularCamera == o.equiAngularCamera && equiAngularOnly == o.equiAngularOnly && pathTracer == o.pathTracer;
}

BdptAllocation pilotAllocation() { return BdptAllocation{}; }

std::vector<BdptAllocation> candidateAllocations(ConnectMode connect) {
    const bool ea = connect != ConnectMode::Density;
    std::vector<BdptAllocation> out;
    auto add = [&](BdptAllocation a) {
        if (!ea) a.equiAngularLight = a.equiAngularCamera = false;
        if (!a.lightSubpaths || !a.lightTracing) a.equiAngularCamera = false;
        if (!a.lightSubpaths) a.lightTracing = false, a.generalConnection = 0;
        if (!a.equiAngularLight && !a.equiAngularCamera) a.equiAngularOnly = false;
        for (const BdptAllocation& b : out)
            if (b == a) return;
        out.push_back(a);
    };
    for (bool eaLight : {true, false}) add(BdptAllocation{false, false, 0.0f, eaLight, false});
    BdptAllocation pathTracer{false, false, 0.0f, true, false};
    pathTracer.pathTracer = true;
    add(pathTracer);
    for (float p : {0.25f, 1.0f, 0.0f})
        for (bool eaLight : {true, false})
            for (bool eaCamera : {true, false}) add(BdptAllocation{true, true, p, eaLight, eaCamera});
    for (float p : {0.25f, 1.0f})
        for (bool eaLight : {true, false}) add(BdptAllocation{true, false, p, eaLight, false});
    const size_t plain = out.size();
    for (size_t j = 0; j < plain; ++j)
        if (!out[j].pathTracer && (out[j].equiAngularLight || out[j].equiAngularCamera)) {
            BdptAllocation a = out[j];
            a.equiAngularOnly = true;
            add(a);
        }
    return out;
}

bool allocationNamed(const std::string& name, ConnectMode connect, BdptAllocation* out) {
    for (const BdptAllocation& a : candidateAllocations(connect))
        if (a.name() == name) {
            *out = a;
            return true;
        }
    return false;
}

}  // namespace brume
