// glTF loader: reading the file through tinygltf, and turning every problem into a one-line
// SceneError that names the file and the offending field.
#include <cctype>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "brume/scene/gltf_detail.h"

namespace brume::gltf {

namespace {

// tinygltf messages may span several lines and quote whole data: URIs. Make them one short line.
std::string tidy(const std::string& text) {
    std::string out, line;
    std::istringstream lines(text);
    while (std::getline(lines, line)) {
        std::istringstream words(line);
        std::string word, kept;
        while (words >> word) {
            if (word.size() > 80) word = word.substr(0, 60) + "...";
            kept += (kept.empty() ? "" : " ") + word;
        }
        if (!kept.empty()) out += (out.empty() ? "" : "; ") + kept;
    }
    if (out.size() > 400) out = out.substr(0, 400) + "...";
    return out.empty() ? "unknown error" : out;
}

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

bool contains(const std::string& s, const char* what) { return s.find(what) != std::string::npos; }

// Which part of the file a tinygltf error is about.
std::string fieldOfTinygltfError(const std::string& err, bool binary) {
    if (contains(err, "json.exception")) return "JSON";
    if (binary && (contains(err, "GLB") || contains(err, "glTF Binary") || contains(err, "glTF binary") ||
                   contains(err, "Chunk") || contains(err, "magic")))
        return "GLB";
    if (contains(err, "File not found") || contains(err, "File read error") || contains(err, "File is empty") ||
        contains(err, "Buffer") || contains(err, "buffer"))
        return "buffers";
    if (contains(err, "image[")) return "images";
    if (contains(err, "accessor")) return "accessors";
    if (contains(err, "camera")) return "cameras";
    return "glTF";
}

// tinygltf decodes images given by URI while parsing; images stored in a buffer view are left
// for decodeImage (gltf_material.cpp) because tinygltf reads them without a bounds check.
bool loadImageData(tinygltf::Image* image, int index, std::string* err, std::string* warn, int width, int height,
                   const unsigned char* bytes, int size, void*) {
    if (image->bufferView != -1) return true;
    // No options: stb_image expands grey and grey + alpha to RGBA.
    return tinygltf::LoadImageData(image, index, err, warn, width, height, bytes, size, nullptr);
}

uint32_t readU32(const unsigned char* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// tinygltf's own messages for a short GLB are vague ("Invalid glTF binary."); say what is wrong.
void checkGlbHeader(const Source& src, std::ifstream& file, std::uintmax_t size) {
    unsigned char header[20] = {};
    file.read(reinterpret_cast<char*>(header), sizeof header);
    if (size < 12) src.fail("GLB", "truncated: " + std::to_string(size) + " bytes, the GLB header alone needs 12");
    if (std::memcmp(header, "glTF", 4) != 0) src.fail("GLB", "not a GLB file (the magic is not 'glTF')");
    uint32_t length = readU32(header + 8);
    if (length > size)
        src.fail("GLB", "truncated: the header declares " + std::to_string(length) + " bytes, the file has " +
                            std::to_string(size));
    if (size >= 20 && 20ull + readU32(header + 12) > length)
        src.fail("GLB", "truncated: the JSON chunk runs past the declared length " + std::to_string(length));
}

}  // namespace

void Source::fail(const std::string& field, const std::string& problem) const {
    std::string message = path + ": " + field + ": " + problem;
    for (char& c : message)
        if (c == '\n' || c == '\r') c = ' ';
    while (!message.empty() && message.back() == ' ') message.pop_back();
    throw SceneError(message);
}

std::string num(double v) {
    std::ostringstream s;
    s.precision(9);
    s << v;
    return s.str();
}

std::string at(const std::string& field, size_t i) { return field + "[" + std::to_string(i) + "]"; }

int checkIndex(const Source& src, int index, size_t count, const std::string& field, const char* noun) {
    if (index < 0 || size_t(index) >= count)
        src.fail(field, std::string(noun) + " " + std::to_string(index) + " out of range (" + std::to_string(count) +
                            " in file)");
    return index;
}

tinygltf::Model readModel(const Source& src) {
    const std::string ext = lowerExtension(src.path);
    const bool binary = ext == ".glb";
    if (!binary && ext != ".gltf")
        src.fail("file", (ext.empty() ? std::string("no file extension") : "unsupported file extension '" + ext + "'") +
                             " (expected .gltf or .glb)");

    std::error_code ec;
    if (std::filesystem::is_directory(src.path, ec)) src.fail("file", "is a directory");
    std::ifstream file(src.path, std::ios::binary);
    if (!file) src.fail("file", std::string("cannot open: ") + std::strerror(errno));
    std::uintmax_t size = std::filesystem::file_size(src.path, ec);
    if (ec) src.fail("file", "cannot read its size: " + ec.message());
    if (size == 0) src.fail("file", "is empty");
    if (binary) checkGlbHeader(src, file, size);
    file.close();

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&loadImageData, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, src.path)
                     : loader.LoadASCIIFromFile(&model, &err, &warn, src.path);
    if (!ok || !err.empty()) {
        std::string field = fieldOfTinygltfError(err, binary);
        src.fail(field, (field == "buffers" ? "cannot load: " : "") + tidy(err));
    }

    // tinygltf only warns about an image file it cannot read.
    for (size_t i = 0; i < model.images.size(); ++i) {
        const tinygltf::Image& image = model.images[i];
        if (image.bufferView != -1 || !image.image.empty()) continue;
        std::string uri = image.uri.size() > 80 ? image.uri.substr(0, 60) + "..." : image.uri;
        src.fail(at("images", i) + ".uri",
                 "cannot load '" + uri + "'" + (warn.empty() ? std::string() : " (" + tidy(warn) + ")"));
    }
    return model;
}

std::string besideScene(const Source& src, const std::string& relative) {
    if (relative.empty() || relative[0] == '/') return relative;
    const size_t slash = src.path.find_last_of('/');
    return slash == std::string::npos ? relative : src.path.substr(0, slash + 1) + relative;
}

namespace {
// A URI's %XX escapes decoded, as tinygltf decodes them before opening the file.
std::string decodeUri(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit((unsigned char)uri[i + 1]) &&
            std::isxdigit((unsigned char)uri[i + 2])) {
            out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}
}  // namespace

void addReferencedFiles(const Source& src, const tinygltf::Model& model, std::vector<std::string>& files) {
    auto add = [&](const std::string& uri) {
        if (uri.empty() || uri.rfind("data:", 0) == 0) return;
        const std::string path = besideScene(src, decodeUri(uri));
        if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
    };
    for (const tinygltf::Buffer& b : model.buffers) add(b.uri);
    for (const tinygltf::Image& image : model.images)
        if (image.bufferView == -1) add(image.uri);
}

const tinygltf::Value* member(const tinygltf::Value& object, const char* key) {
    if (!object.IsObject() || !object.Has(key)) return nullptr;
    const tinygltf::Value& v = object.Get(key);
    return v.Type() == tinygltf::NULL_TYPE ? nullptr : &v;
}

double finiteNumber(const Source& src, const tinygltf::Value& v, const std::string& field) {
    if (!v.IsNumber()) src.fail(field, "expected a number");
    double d = v.GetNumberAsDouble();
    if (!std::isfinite(d)) src.fail(field, "not a finite number (" + num(d) + ")");
    return d;
}

int integer(const Source& src, const tinygltf::Value& v, const std::string& field) {
    if (!v.IsNumber()) src.fail(field, "expected an integer");
    double d = v.GetNumberAsDouble();
    if (!(d == std::floor(d) && d >= double(std::numeric_limits<int>::min()) &&
          d <= double(std::numeric_limits<int>::max())))
        src.fail(field, "expected an integer, got " + num(d));
    return int(d);
}

}  // namespace brume::gltf
