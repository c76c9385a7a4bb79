// A value per colour channel in double: the free-flight densities of coloured media, kept per
// channel so that distance sampling can be weighed across channels (docs/path-tracer.md,
// "coloured media"). Double because products of densities over long edges leave float's range.
#pragma once
#include "brume/math/vec3.h"

namespace brume {

template <class T>
struct ChannelsOf {
    T v[3];
    ChannelsOf(T a = 1) : v{a, a, a} {}
    ChannelsOf(T r, T g, T b) : v{r, g, b} {}
    T operator[](int c) const { return v[c]; }
    T& operator[](int c) { return v[c]; }
    ChannelsOf& operator*=(const ChannelsOf& o) {
        for (int c = 0; c < 3; ++c) v[c] *= o.v[c];
        return *this;
    }
    ChannelsOf operator*(const ChannelsOf& o) const { return ChannelsOf(*this) *= o; }
    ChannelsOf operator*(T s) const { return {v[0] * s, v[1] * s, v[2] * s}; }
    // Σ_c w_c·v_c: the density of a mixture that picks channel c with probability w_c.
    T mix(Spectrum w) const { return w.x * v[0] + w.y * v[1] + w.z * v[2]; }
};

using Channels = ChannelsOf<double>;
// MIS sums over channels: ratios between channels' densities reach 1e±300 within a path
// (a dense channel far along a ray), and their squares leave double's range.
using WideChannels = ChannelsOf<long double>;

inline Channels operator*(double s, const Channels& c) { return c * s; }

}  // namespace brume
