#include "brume/cli/build_identity.h"

#include <cstdio>
#include <stdexcept>

#include "brume/render/fnv1a.h"

namespace brume::cli {

namespace {

std::string hashExecutable() {
    uint64_t hash = 0;
    try {
        hash = fnv1a64File("/proc/self/exe");
    } catch (const std::runtime_error& e) {
        throw std::runtime_error(std::string(e.what()) + " (cannot identify this brume build)");
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
    return hex;
}

}  // namespace

const std::string& buildIdentity() {
    static const std::string identity = hashExecutable();  // a failure is retried by the next call
    return identity;
}

}  // namespace brume::cli
