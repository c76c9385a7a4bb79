#include "brume/film/image_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
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

// PFM: "PF\n<w> <h>\n-1.0\n", then little-endian floats, bottom row first. Written here:
// OpenImageIO 2.4 (Debian 12) reads PFM but has no PFM writer (its PNM writer makes 8-bit
// P6 files).
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

// 8-bit sRGB: clamped to [0, 1] (NaN to 0), then OpenImageIO's linear → sRGB transfer
// function and its rounding to 8 bits.
std::vector<unsigned char> srgbBytes(int width, int height, const std::vector<float>& rgb) {
    std::vector<float> clamped(rgb.size());
    for (size_t i = 0; i < rgb.size(); ++i) clamped[i] = std::isnan(rgb[i]) ? 0.0f : std::clamp(rgb[i], 0.0f, 1.0f);
    OIIO::ImageBuf linear(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT), clamped.data());
    OIIO::ImageBuf encoded = OIIO::ImageBufAlgo::colorconvert(linear, "linear", "sRGB");
    std::vector<unsigned char> bytes(rgb.size());
    if (encoded.has_error() || !encoded.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::UINT8, bytes.data()))
        throw std::runtime_error("sRGB encoding: " + firstLine(encoded.geterror()));
    return bytes;
}

// sRGB-encoded float RGB (as read from a PNG) to linear, in place.
void decodeSrgb(int width, int height, std::vector<float>& rgb) {
    OIIO::ImageBuf encoded(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT), rgb.data());
    OIIO::ImageBuf linear = OIIO::ImageBufAlgo::colorconvert(encoded, "sRGB", "linear");
    if (linear.has_error() || !linear.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, rgb.data()))
        throw std::runtime_error("sRGB decoding: " + firstLine(linear.geterror()));
}

void writeWithOiio(const std::string& file, ImageFormat format, int width, int height,
                   const std::vector<float>& rgb, const std::vector<ImageLayer>& layers) {
    std::vector<unsigned char> srgb;
    if (format == ImageFormat::Png) srgb = srgbBytes(width, height, rgb);
    auto out = OIIO::ImageOutput::create(file);
    if (!out) throw std::runtime_error(firstLine(OIIO::geterror()));
    OIIO::TypeDesc type = format == ImageFormat::Png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
    const int channels = 3 + 3 * int(layers.size());
    OIIO::ImageSpec spec(width, height, channels, type);
    std::vector<float> all;  // R, G, B, then each layer's three, per pixel
    if (!layers.empty()) {
        std::vector<std::string> names = {"R", "G", "B"};
        for (const ImageLayer& l : layers)
            for (const std::string& c : l.channels) names.push_back(l.name + "." + c);
        spec.channelnames = names;
        const size_t n = size_t(width) * size_t(height);
        all.resize(n * size_t(channels));
        for (size_t i = 0; i < n; ++i) {
            float* o = &all[i * size_t(channels)];
            for (int c = 0; c < 3; ++c) o[c] = rgb[3 * i + size_t(c)];
            for (size_t l = 0; l < layers.size(); ++l)
                for (int c = 0; c < 3; ++c) o[3 + 3 * l + size_t(c)] = layers[l].values[3 * i + size_t(c)];
        }
    }
    spec.attribute("oiio:ColorSpace", format == ImageFormat::Png ? "sRGB" : "linear");
    // An empty capture date: OpenImageIO would stamp the time of writing into EXR headers, and
    // the same render (straight, or interrupted and resumed) must give the same bytes.
    spec.attribute("DateTime", "");
    bool ok = out->open(file, spec);
    if (ok) {
        if (format == ImageFormat::Png) {
            ok = out->write_image(OIIO::TypeDesc::UINT8, srgb.data());
        } else {
            ok = out->write_image(OIIO::TypeDesc::FLOAT, layers.empty() ? rgb.data() : all.data());
        }
    }
    std::string message = ok ? "" : out->geterror();
    if (!out->close() && ok) {
        ok = false;
        message = out->geterror();
    }
    if (!ok) throw std::runtime_error(firstLine(message));
}

// PFM holds raw floats: a header promising more than the file holds is refused before the
// pixels are allocated.
void checkPfmSize(const std::string& path, const OIIO::ImageSpec& spec) {
    struct stat st;
    uint64_t needed = uint64_t(spec.width) * uint64_t(spec.height) * uint64_t(spec.nchannels) * 4;
    if (::stat(path.c_str(), &st) != 0 || uint64_t(st.st_size) < needed)
        fail(path, "PFM file is truncated (its header promises " + std::to_string(spec.width) + "x" +
                       std::to_string(spec.height) + " pixels)");
}

std::vector<float> readWithOiio(const std::string& path, ImageFormat format, int* width, int* height) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) fail(path, firstLine(OIIO::geterror()));
    const OIIO::ImageSpec& spec = in->spec();
    int w = spec.width, h = spec.height, channels = spec.nchannels;
    if (w <= 0 || h <= 0 || channels <= 0) fail(path, "empty image");
    if (format == ImageFormat::Pfm) checkPfmSize(path, spec);
    std::vector<float> all(size_t(w) * size_t(h) * size_t(channels));
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, all.data())) {
        std::string message = in->geterror();  // OpenImageIO 2.4 says nothing about a short PFM
        fail(path, message.empty() ? "truncated or damaged pixel data" : firstLine(message));
    }
    in->close();

    // One channel is replicated to three, a fourth (alpha) dropped.
    std::vector<float> rgb(3 * size_t(w) * size_t(h));
    for (size_t i = 0; i < size_t(w) * size_t(h); ++i)
        for (int c = 0; c < 3; ++c) rgb[3 * i + size_t(c)] = all[i * size_t(channels) + size_t(channels >= 3 ? c : 0)];
    if (format == ImageFormat::Png) {
        try {
            decodeSrgb(w, h, rgb);
        } catch (const std::exception& e) {
            fail(path, e.what());
        }
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
    writeImage(path, width, height, rgb, {});
}

void writeImage(const std::string& path, int width, int height, const std::vector<float>& rgb,
                const std::vector<ImageLayer>& layers) {
    ImageFormat format;
    try {
        format = imageFormatFor(path);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(e.what());
    }
    checkSize(path, width, height, rgb);
    if (!layers.empty() && format != ImageFormat::Exr) fail(path, "extra layers (--aov) need an .exr file");
    for (const ImageLayer& l : layers) checkSize(path, width, height, l.values);
    std::string tmp = temporaryPathFor(path);
    try {
        if (format == ImageFormat::Pfm) writePfm(tmp, width, height, rgb);
        else writeWithOiio(tmp, format, width, height, rgb, layers);
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
    return readWithOiio(path, format, width, height);
}

}  // namespace brume
