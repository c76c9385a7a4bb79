#include "brume/cli/scene_identity.h"

#include <cstdio>

#include "brume/render/fnv1a.h"

namespace brume {

namespace {

std::string hex(uint64_t h) {
    char s[20];
    std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(h));
    return s;
}

// path as the scene names it: relative to the scene file's directory where it is beside it.
std::string shownName(const std::string& scenePath, const std::string& path) {
    const size_t slash = scenePath.find_last_of('/');
    const std::string dir = slash == std::string::npos ? std::string() : scenePath.substr(0, slash + 1);
    return !dir.empty() && path.compare(0, dir.size(), dir) == 0 ? path.substr(dir.size()) : path;
}

}  // namespace

CheckpointSettings sceneFileSettings(const SceneDescription& desc) {
    CheckpointSettings settings;
    for (size_t i = 0; i < desc.files.size(); ++i) {
        const std::string name =
            i == 0 ? std::string("the scene file's FNV-1a hash") : "the FNV-1a hash of " + shownName(desc.path, desc.files[i]);
        settings.emplace_back(name, hex(fnv1a64File(desc.files[i])));
    }
    return settings;
}

uint64_t sceneContentHash(const SceneDescription& desc) {
    if (desc.files.size() == 1) return fnv1a64File(desc.files[0]);
    Fnv1a64 h;
    for (const std::string& file : desc.files) {
        const uint64_t f = fnv1a64File(file);
        h.add(file.c_str(), file.size() + 1);
        h.add(&f, sizeof f);
    }
    return h.value();
}

}  // namespace brume
