// tinygltf and stb_image compiled into the fuzz target, so that libFuzzer sees their branches
// and the sanitizers check their memory accesses: Debian ships both as shared libraries,
// uninstrumented. These definitions take precedence over those of libtinygltf and libstb for
// the whole process. Needs nlohmann-json3-dev and libstb-dev (tests/fuzz/run.sh).
#define TINYGLTF_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <tiny_gltf.h>
