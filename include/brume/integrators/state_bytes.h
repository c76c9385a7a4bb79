// The bytes of an integrator's saved state (Integrator::saveState): values appended raw, and
// read back with bounds checks (std::runtime_error for truncated or malformed bytes). Shared
// by the allocation planner and its duel.
#pragma once
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace brume {

template <class T> void putBytes(std::string& out, const T& v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); }
template <class T> void putVector(std::string& out, const std::vector<T>& v) {
    putBytes(out, uint64_t(v.size()));
    out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

struct StateReader {
    const std::string& s;
    size_t at = 0;
    template <class T> T get() {
        if (s.size() - at < sizeof(T)) throw std::runtime_error("allocation state is truncated");
        T v;
        std::memcpy(&v, s.data() + at, sizeof v);
        at += sizeof v;
        return v;
    }
    // A vector of at most `most` values.
    template <class T> std::vector<T> getVector(size_t most) {
        const uint64_t n = get<uint64_t>();
        if (n > most || (s.size() - at) / sizeof(T) < n) throw std::runtime_error("allocation state is malformed");
        std::vector<T> v(n);
        if (n > 0) std::memcpy(v.data(), s.data() + at, n * sizeof(T));
        at += n * sizeof(T);
        return v;
    }
};

}  // namespace brume
