// libFuzzer target for the glTF loader (tests/fuzz/run.sh builds and runs it). Each input is
// written to a file, scene.glb if it starts with the GLB magic and scene.gltf otherwise, in a
// directory of its own, and loaded. SceneError is the loader's answer to a bad file; a crash,
// a sanitizer report or any other exception is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "brume/scene/gltf_loader.h"

namespace {

// A fresh directory under $TMPDIR (or /tmp), removed when the fuzzer exits normally. Never
// destroyed, so that the exit handler can still use it.
const std::string& workDir() {
    static const std::string* dir = [] {
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/fuzz_gltf_loader.XXXXXX";
        if (!mkdtemp(pattern.data())) std::abort();
        std::atexit([] { std::filesystem::remove_all(workDir()); });
        return new std::string(pattern);
    }();
    return *dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    const std::string path = workDir() + (glb ? "/scene.glb" : "/scene.gltf");
    {
        std::ofstream file(path, std::ios::binary | std::ios::trunc);
        file.write(reinterpret_cast<const char*>(data), std::streamsize(size));
        if (!file) std::abort();
    }
    try {
        brume::loadGltf(path);
    } catch (const brume::SceneError&) {
    }
    return 0;
}
