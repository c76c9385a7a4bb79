#include "brume/film/image_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace brume {

namespace {

std::string lowerExtension(const std::string& path) {
    size_t slash = path.find_last_of('/');
    size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

std::string directoryOf(const std::string& path) {
    size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    if (slash == 0) return "/";
    return path.substr(0, slash);
}

// "dir/name.exr" -> "dir/name.tmp-<pid>.exr": beside the target, same extension (OpenImageIO
// picks the format by it).
std::string temporaryPathFor(const std::string& path) {
    size_t slash = path.find_last_of('/');
    size_t dot = path.find_last_of('.');
    std::string tag = ".tmp-" + std::to_string(long(::getpid()));
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + tag;
    return path.substr(0, dot) + tag + path.substr(dot);
}

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw std::runtime_error(path + ": " + problem);
}

// One line of an OpenImageIO message.
std::string firstLine(std::string message) {
    size_t nl = message.find('\n');
    if (nl != std::string::npos) message.resize(nl);
    return message.empty() ? "unknown OpenImageIO error" : message;
}

void checkSize(const std::string& path, int width, int height, const std::vector<float>& rgb) {
    if (width <= 0 || height <= 0) fail(path, "image size must be positive");
    if (rgb.size() != 3 * size_t(width) * size_t(height))
        fail(path, "pixel buffer holds " + std::to_string(rgb.size()) + " values, expected 3 x " +
                       std::to_string(width) + " x " + std::to_string(height));
}

void putLittleEndian(float f, unsigned char* out) {
    uint32_t bits;
    std::memcpy(&bits, &f, 4);
    out[0] = static_cast<unsigned char>(bits);
    out[1] = static_cast<unsigned char>(bits >> 8);
    out[2] = static_cast<unsigned char>(bits >> 16);
    out[3] = static_cast<unsigned char>(bits >> 24);
}

float getFloat(const unsigned char* in, bool littleEndian) {
    uint32_t bits = littleEndian ? (uint32_t(in[0]) | uint32_t(in[1]) << 8 | uint32_t(in[2]) << 16 |
                                    uint32_t(in[3]) << 24)
                                 : (uint32_t(in[3]) | uint32_t(in[2]) << 8 | uint32_t(in[1]) << 16 |
                                    uint32_t(in[0]) << 24);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

// PFM: "PF\n<w> <h>\n-1.0\n", then little-endian floats, bottom row first.
void writePfm(const std::string& file, int width, int height, const std::vector<float>& rgb) {
    std::FILE* f = std::fopen(file.c_str(), "wb");
    if (!f) throw std::runtime_error(std::strerror(errno));
    bool ok = std::fprintf(f, "PF\n%d %d\n-1.0\n", width, height) > 0;
    std::vector<unsigned char> row(size_t(width) * 12);
    for (int y = height - 1; ok && y >= 0; --y) {
        const float* src = &rgb[3 * size_t(y) * size_t(width)];
        for (size_t i = 0; i < size_t(width) * 3; ++i) putLittleEndian(src[i], &row[4 * i]);
        ok = std::fwrite(row.data(), 1, row.size(), f) == row.size();
    }
    int savedErrno = errno;
    if (std::fclose(f) != 0 && ok) {
        ok = false;
        savedErrno = errno;
    }
    if (!ok) throw std::runtime_error(std::string("cannot write: ") + std::strerror(savedErrno));
}

float srgbEncode(float linear) {
    float c = std::isnan(linear) ? 0.0f : std::clamp(linear, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

float srgbDecode(float encoded) {
    return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

void writeWithOiio(const std::string& file, ImageFormat format, int width, int height,
                   const std::vector<float>& rgb) {
    auto out = OIIO::ImageOutput::create(file);
    if (!out) throw std::runtime_error(firstLine(OIIO::geterror()));
    OIIO::TypeDesc type = format == ImageFormat::Png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
    OIIO::ImageSpec spec(width, height, 3, type);
    spec.attribute("oiio:ColorSpace", format == ImageFormat::Png ? "sRGB" : "linear");
    // An empty capture date: OpenImageIO would stamp the time of writing into EXR headers, and
    // the same render (straight, or interrupted and resumed) must give the same bytes.
    spec.attribute("DateTime", "");
    bool ok = out->open(file, spec);
    if (ok) {
        if (format == ImageFormat::Png) {
            std::vector<unsigned char> bytes(rgb.size());
            for (size_t i = 0; i < rgb.size(); ++i)
                bytes[i] = static_cast<unsigned char>(std::lround(srgbEncode(rgb[i]) * 255.0f));
            ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
        } else {
            ok = out->write_image(OIIO::TypeDesc::FLOAT, rgb.data());
        }
    }
    std::string message = ok ? "" : out->geterror();
    if (!out->close() && ok) {
        ok = false;
        message = out->geterror();
    }
    if (!ok) throw std::runtime_error(firstLine(message));
}

std::vector<float> readPfm(const std::string& path, int* width, int* height) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) fail(path, std::strerror(errno));
    std::vector<unsigned char> data;
    unsigned char buffer[65536];
    size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) data.insert(data.end(), buffer, buffer + n);
    bool readError = std::ferror(f) != 0;
    std::fclose(f);
    if (readError) fail(path, "read error");

    // Header: three whitespace-separated tokens after the magic, then one whitespace byte.
    size_t pos = 0;
    auto token = [&]() -> std::string {
        while (pos < data.size() && std::isspace(data[pos])) ++pos;
        size_t begin = pos;
        while (pos < data.size() && !std::isspace(data[pos])) ++pos;
        return std::string(data.begin() + begin, data.begin() + pos);
    };
    std::string magic = token();
    if (magic != "PF" && magic != "Pf") fail(path, "not a PFM file");
    int channels = magic == "PF" ? 3 : 1;
    long w = 0, h = 0;
    double scale = 0;
    try {
        w = std::stol(token());
        h = std::stol(token());
        scale = std::stod(token());
    } catch (const std::exception&) {
        fail(path, "bad PFM header");
    }
    if (w <= 0 || h <= 0 || w > (1 << 20) || h > (1 << 20) || scale == 0) fail(path, "bad PFM header");
    ++pos;  // the single whitespace byte before the data
    size_t expected = size_t(w) * size_t(h) * size_t(channels) * 4;
    if (pos > data.size() || data.size() - pos < expected) fail(path, "PFM file is truncated");
    bool little = scale < 0;

    std::vector<float> rgb(3 * size_t(w) * size_t(h));
    const unsigned char* src = data.data() + pos;
    for (long row = 0; row < h; ++row) {
        long y = h - 1 - row;  // bottom row first in the file
        for (long x = 0; x < w; ++x) {
            float* dst = &rgb[3 * (size_t(y) * size_t(w) + size_t(x))];
            const unsigned char* p = src + 4 * size_t(channels) * (size_t(row) * size_t(w) + size_t(x));
            for (int c = 0; c < 3; ++c) dst[c] = getFloat(p + 4 * (channels == 3 ? c : 0), little);
        }
    }
    *width = int(w);
    *height = int(h);
    return rgb;
}

std::vector<float> readWithOiio(const std::string& path, ImageFormat format, int* width, int* height) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) fail(path, firstLine(OIIO::geterror()));
    const OIIO::ImageSpec& spec = in->spec();
    int w = spec.width, h = spec.height, channels = spec.nchannels;
    if (w <= 0 || h <= 0 || channels <= 0) fail(path, "empty image");
    std::vector<float> all(size_t(w) * size_t(h) * size_t(channels));
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, all.data())) fail(path, firstLine(in->geterror()));
    in->close();

    std::vector<float> rgb(3 * size_t(w) * size_t(h));
    for (size_t i = 0; i < size_t(w) * size_t(h); ++i)
        for (int c = 0; c < 3; ++c) {
            float v = all[i * size_t(channels) + size_t(channels >= 3 ? c : 0)];
            rgb[3 * i + size_t(c)] = format == ImageFormat::Png ? srgbDecode(v) : v;
        }
    *width = w;
    *height = h;
    return rgb;
}

}  // namespace

ImageFormat imageFormatFor(const std::string& path) {
    std::string ext = lowerExtension(path);
    if (ext == ".exr") return ImageFormat::Exr;
    if (ext == ".pfm") return ImageFormat::Pfm;
    if (ext == ".png") return ImageFormat::Png;
    if (ext.empty()) throw std::invalid_argument(path + ": no file extension to pick the format (use .exr, .pfm or .png)");
    throw std::invalid_argument(path + ": unknown image format '" + ext + "' (use .exr, .pfm or .png)");
}

void checkImageWritable(const std::string& path) {
    imageFormatFor(path);
    struct stat st;
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) fail(path, "is a directory");
    // Create (and remove) the temporary file writeImage will use: this answers "can we write
    // here" exactly, for root and read-only file systems too.
    std::string tmp = temporaryPathFor(path);
    int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0) fail(path, "cannot create a file in " + directoryOf(path) + ": " + std::strerror(errno));
    ::close(fd);
    ::unlink(tmp.c_str());
}

void writeImage(const std::string& path, int width, int height, const std::vector<float>& rgb) {
    ImageFormat format;
    try {
        format = imageFormatFor(path);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(e.what());
    }
    checkSize(path, width, height, rgb);
    std::string tmp = temporaryPathFor(path);
    try {
        if (format == ImageFormat::Pfm) writePfm(tmp, width, height, rgb);
        else writeWithOiio(tmp, format, width, height, rgb);
        if (std::rename(tmp.c_str(), path.c_str()) != 0)
            throw std::runtime_error(std::string("cannot rename the temporary file into place: ") +
                                     std::strerror(errno));
    } catch (const std::exception& e) {
        ::unlink(tmp.c_str());
        fail(path, e.what());
    }
}

std::vector<float> readImage(const std::string& path, int* width, int* height) {
    ImageFormat format;
    try {
        format = imageFormatFor(path);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(e.what());
    }
    if (format == ImageFormat::Pfm) return readPfm(path, width, height);
    return readWithOiio(path, format, width, height);
}

}  // namespace brume
