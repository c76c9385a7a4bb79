#include "brume/render/checkpoint.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "brume/render/fnv1a.h"

namespace brume {

namespace {

constexpr char kMagic[8] = {'B', 'R', 'U', 'M', 'E', 'C', 'K', 'P'};
constexpr uint32_t kMaxString = 4096;
constexpr uint32_t kMaxSettings = 256;
constexpr size_t kChunk = 8192;  // sums converted per write/read

std::string temporaryPathFor(const std::string& path) { return path + ".tmp-" + std::to_string(long(::getpid())); }

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw std::runtime_error(path + ": " + problem);
}

void putU64(uint64_t v, unsigned char* out) {
    for (int i = 0; i < 8; ++i) out[i] = static_cast<unsigned char>(v >> (8 * i));
}

uint64_t getU64(const unsigned char* in) {
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(in[i]) << (8 * i);
    return v;
}

// Appends to a FILE*, hashing every byte; remembers the first failure (errno) instead of
// throwing, so the caller can clean up in one place.
class Writer {
public:
    explicit Writer(std::FILE* f) : f_(f) {}
    void bytes(const void* data, size_t n) {
        hash_.add(data, n);
        if (error_ == 0 && std::fwrite(data, 1, n, f_) != n) error_ = errno ? errno : EIO;
    }
    void u8(uint8_t v) { bytes(&v, 1); }
    void u32(uint32_t v) {
        unsigned char b[4] = {static_cast<unsigned char>(v), static_cast<unsigned char>(v >> 8),
                              static_cast<unsigned char>(v >> 16), static_cast<unsigned char>(v >> 24)};
        bytes(b, 4);
    }
    void i32(int32_t v) { u32(static_cast<uint32_t>(v)); }
    void u64(uint64_t v) {
        unsigned char b[8];
        putU64(v, b);
        bytes(b, 8);
    }
    void str(const std::string& s) {
        u32(uint32_t(s.size()));
        bytes(s.data(), s.size());
    }
    // Film sums: each as two u64, low then high half of the two's complement.
    void sums(const std::vector<Film::Sum>& v) {
        std::vector<unsigned char> buffer(16 * kChunk);
        for (size_t i = 0; i < v.size(); i += kChunk) {
            size_t n = std::min(kChunk, v.size() - i);
            for (size_t k = 0; k < n; ++k) {
                const unsigned __int128 bits = static_cast<unsigned __int128>(v[i + k]);
                putU64(uint64_t(bits), &buffer[16 * k]);
                putU64(uint64_t(bits >> 64), &buffer[16 * k + 8]);
            }
            bytes(buffer.data(), 16 * n);
        }
    }
    uint64_t hash() const { return hash_.value(); }
    int error() const { return error_; }

private:
    std::FILE* f_;
    Fnv1a64 hash_;
    int error_ = 0;
};

// Reads from a FILE* of known size, hashing every byte; throws on anything short.
class Reader {
public:
    Reader(std::FILE* f, const std::string& path, uint64_t size) : f_(f), path_(path), remaining_(size) {}
    uint64_t remaining() const { return remaining_; }
    void bytes(void* out, size_t n) {
        if (n > remaining_ || std::fread(out, 1, n, f_) != n) fail(path_, "truncated checkpoint");
        remaining_ -= n;
        hash_.add(out, n);
    }
    uint8_t u8() {
        uint8_t v;
        bytes(&v, 1);
        return v;
    }
    uint32_t u32() {
        unsigned char b[4];
        bytes(b, 4);
        return uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
    }
    int32_t i32() { return static_cast<int32_t>(u32()); }
    uint64_t u64() {
        unsigned char b[8];
        bytes(b, 8);
        return getU64(b);
    }
    std::string str() {
        uint32_t n = u32();
        if (n > kMaxString) fail(path_, "corrupt checkpoint (a string of " + std::to_string(n) + " bytes)");
        std::string s(n, '\0');
        bytes(s.data(), n);
        return s;
    }
    std::vector<Film::Sum> sums(size_t count) {
        std::vector<Film::Sum> v(count);
        std::vector<unsigned char> buffer(16 * kChunk);
        for (size_t i = 0; i < count; i += kChunk) {
            size_t n = std::min(kChunk, count - i);
            bytes(buffer.data(), 16 * n);
            for (size_t k = 0; k < n; ++k) {
                const unsigned __int128 bits =
                    (static_cast<unsigned __int128>(getU64(&buffer[16 * k + 8])) << 64) | getU64(&buffer[16 * k]);
                v[i + k] = static_cast<Film::Sum>(bits);
            }
        }
        return v;
    }
    uint64_t hash() const { return hash_.value(); }

private:
    std::FILE* f_;
    const std::string& path_;
    uint64_t remaining_;
    Fnv1a64 hash_;
};

// Closes the file on every way out of readCheckpoint.
struct FileCloser {
    std::FILE* f;
    ~FileCloser() {
        if (f) std::fclose(f);
    }
};

}  // namespace

void writeCheckpoint(const std::string& path, const std::string& scenePath, const CheckpointSettings& settings,
                     const Film& film, uint64_t nonFinite, const std::string& integratorState) {
    const std::string tmp = temporaryPathFor(path);
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) fail(path, std::string("cannot write checkpoint: ") + std::strerror(errno));
    Writer w(f);
    w.bytes(kMagic, sizeof kMagic);
    w.u32(kCheckpointVersion);
    w.str(scenePath);
    w.u32(uint32_t(settings.size()));
    for (const auto& [name, value] : settings) {
        w.str(name);
        w.str(value);
    }
    w.i32(film.width());
    w.i32(film.height());
    w.i32(film.passes());
    w.u64(nonFinite);
    w.u8(film.hasSplats() ? 1 : 0);
    w.u8(film.tracksNoise() ? 1 : 0);
    w.u64(integratorState.size());
    w.sums(film.sums());
    if (film.tracksNoise()) {
        for (int32_t n : film.sampleCounts()) w.i32(n);
        w.sums(film.squares());
    }
    w.bytes(integratorState.data(), integratorState.size());
    w.u64(w.hash());

    int error = w.error();
    if (error == 0 && std::fflush(f) != 0) error = errno;
    if (error == 0 && ::fsync(::fileno(f)) != 0) error = errno;  // on disk before it replaces the old one
    if (std::fclose(f) != 0 && error == 0) error = errno;
    if (error == 0 && std::rename(tmp.c_str(), path.c_str()) != 0) error = errno;
    if (error != 0) {
        std::remove(tmp.c_str());
        fail(path, std::string("cannot write checkpoint: ") + std::strerror(error));
    }
}

Checkpoint readCheckpoint(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) fail(path, std::strerror(errno));
    FileCloser closer{f};
    struct stat st;
    if (::fstat(::fileno(f), &st) != 0) fail(path, std::strerror(errno));
    if (S_ISDIR(st.st_mode)) fail(path, "is a directory");
    Reader r(f, path, uint64_t(st.st_size));

    char magic[sizeof kMagic];
    if (r.remaining() < sizeof magic) fail(path, "not a brume checkpoint (too short)");
    r.bytes(magic, sizeof magic);
    if (std::memcmp(magic, kMagic, sizeof magic) != 0) fail(path, "not a brume checkpoint");
    uint32_t version = r.u32();
    if (version != kCheckpointVersion && version != 3)
        fail(path, "checkpoint version " + std::to_string(version) + ", this brume reads versions 3 and " +
                       std::to_string(kCheckpointVersion));
    std::string scenePath = r.str();
    uint32_t count = r.u32();
    if (count > kMaxSettings) fail(path, "corrupt checkpoint (" + std::to_string(count) + " settings)");
    CheckpointSettings settings;
    for (uint32_t i = 0; i < count; ++i) {
        std::string name = r.str();
        settings.emplace_back(std::move(name), r.str());
    }
    int32_t width = r.i32(), height = r.i32(), passes = r.i32();
    uint64_t nonFinite = r.u64();
    uint8_t hasSplats = r.u8();
    uint8_t tracksNoise = version >= 4 ? r.u8() : 0;
    uint64_t stateBytes = r.u64();
    if (width <= 0 || height <= 0 || passes < 0 || hasSplats > 1 || tracksNoise > 1)
        fail(path, "corrupt checkpoint (film " + std::to_string(width) + "x" + std::to_string(height) + ", " +
                       std::to_string(passes) + " passes)");
    // The rest must be exactly the sums and the checksum: checked before allocating, so a
    // damaged header cannot ask for gigabytes.
    const uint64_t values = 3 * uint64_t(width) * uint64_t(height);
    const uint64_t expected = 16 * values + (tracksNoise ? 4 * (values / 3) + 16 * values : 0) + 8;
    if (stateBytes > r.remaining()) fail(path, "truncated checkpoint");
    if (r.remaining() - stateBytes != expected)
        fail(path, r.remaining() - stateBytes < expected ? "truncated checkpoint" : "corrupt checkpoint (trailing bytes)");
    std::vector<Film::Sum> sums = r.sums(size_t(values));
    std::vector<int32_t> samples;
    std::vector<Film::Sum> squares;
    if (tracksNoise) {
        samples.resize(size_t(values / 3));
        for (int32_t& n : samples) n = r.i32();
        squares = r.sums(size_t(values));
    }
    std::string state(size_t(stateBytes), '\0');
    r.bytes(state.data(), state.size());
    const uint64_t computed = r.hash();
    if (r.u64() != computed) fail(path, "corrupt checkpoint (checksum mismatch)");

    Film film(width, height);
    try {
        film.restore(passes, std::move(sums), hasSplats != 0, std::move(samples), std::move(squares));
    } catch (const std::invalid_argument& e) {
        fail(path, std::string("corrupt checkpoint (") + e.what() + ")");
    }
    return Checkpoint{std::move(scenePath), std::move(settings), nonFinite, std::move(film), std::move(state)};
}

std::string checkpointMismatch(const CheckpointSettings& saved, const CheckpointSettings& now) {
    auto find = [](const CheckpointSettings& list, const std::string& name) -> const std::string* {
        for (const auto& [n, v] : list)
            if (n == name) return &v;
        return nullptr;
    };
    for (const auto& [name, value] : now) {
        const std::string* old = find(saved, name);
        if (!old) return name + " is not recorded in the checkpoint";
        if (*old != value) return name + " is " + value + " here but " + *old + " in the checkpoint";
    }
    for (const auto& [name, value] : saved)
        if (!find(now, name)) return "the checkpoint has " + name + " " + value + ", unknown here";
    return "";
}

void checkCheckpointWritable(const std::string& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) fail(path, "is a directory");
    const std::string tmp = temporaryPathFor(path);
    int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0) fail(path, std::string("cannot create a checkpoint file: ") + std::strerror(errno));
    ::close(fd);
    ::unlink(tmp.c_str());
}

}  // namespace brume
