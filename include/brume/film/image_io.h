// Image files. The extension picks the format:
//   .exr  32-bit float linear RGB
//   .pfm  32-bit float linear RGB, portable float map
//   .png  8-bit sRGB-encoded, clamped to [0, 1]
// OpenImageIO reads and writes them all, sRGB conversions included, but for writing PFM
// (OpenImageIO 2.4 has no PFM writer). The same pixels give the same bytes: no dates.
// Pixels are float RGB, row-major, top row first, 3·w·h values.
#pragma once
#include <array>
#include <string>
#include <vector>

namespace brume {

enum class ImageFormat { Exr, Pfm, Png };

// The format for a file name, by its (case-insensitive) extension; throws
// std::invalid_argument naming the path for anything else.
ImageFormat imageFormatFor(const std::string& path);

// Checks, before any work is done, that `path` can be written: the extension is known
// (std::invalid_argument otherwise) and a file can be created beside it (std::runtime_error
// naming the path and the reason otherwise). Leaves nothing behind.
void checkImageWritable(const std::string& path);

// Writes to a temporary file beside `path` ("<stem>.tmp-<pid><ext>") and renames it into
// place, so a half-written image never appears under `path`. Throws std::runtime_error
// ("<path>: <problem>") on failure, after removing the temporary file.
void writeImage(const std::string& path, int width, int height, const std::vector<float>& rgb);

// An extra layer of an EXR file: channels "<name>.<channels[i]>" after R, G, B (Blender's
// compositor shows it as a pass called name), 3 floats per pixel like rgb.
struct ImageLayer {
    std::string name;
    std::array<std::string, 3> channels;
    std::vector<float> values;
};

// writeImage with extra layers; EXR only (std::runtime_error naming the path otherwise).
void writeImage(const std::string& path, int width, int height, const std::vector<float>& rgb,
                const std::vector<ImageLayer>& layers);

// Reads an .exr, .pfm or .png file as linear float RGB (PNG is decoded from sRGB; one channel
// is replicated to three, alpha is dropped). Throws std::runtime_error on failure.
std::vector<float> readImage(const std::string& path, int* width, int* height);

}  // namespace brume
