// FNV-1a, 64 bits: the checksum of checkpoint files and the content hash of scene files.
// Not cryptographic; it catches truncation, bit rot and edited files.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace brume {

class Fnv1a64 {
public:
    void add(const void* data, size_t size) {
        const unsigned char* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < size; ++i) {
            h_ ^= p[i];
            h_ *= 0x100000001b3ull;
        }
    }
    uint64_t value() const { return h_; }

private:
    uint64_t h_ = 0xcbf29ce484222325ull;
};

// The hash of a file's bytes; throws std::runtime_error ("<path>: <problem>") if it cannot be
// read.
uint64_t fnv1a64File(const std::string& path);

}  // namespace brume
