#include "brume/render/fnv1a.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace brume {

uint64_t fnv1a64File(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw std::runtime_error(path + ": " + std::strerror(errno));
    Fnv1a64 hash;
    std::vector<unsigned char> buffer(1 << 16);
    size_t n;
    while ((n = std::fread(buffer.data(), 1, buffer.size(), f)) > 0) hash.add(buffer.data(), n);
    bool failed = std::ferror(f) != 0;
    std::fclose(f);
    if (failed) throw std::runtime_error(path + ": read error");
    return hash.value();
}

}  // namespace brume
