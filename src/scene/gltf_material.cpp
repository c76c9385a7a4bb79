// glTF loader: metallic-roughness materials reduced to brume's material kinds, and the
// sRGB-encoded textures they use decoded to linear RGB.
#include <array>
#include <climits>
#include <cmath>
#include <cstring>

#include "brume/scene/gltf_detail.h"

namespace brume::gltf {

namespace {

double unitInterval(const Source& src, double v, const std::string& field) {
    if (!(std::isfinite(v) && v >= 0 && v <= 1)) src.fail(field, num(v) + " is not in [0, 1]");
    return v;
}

// A number in a material extension, e.g. KHR_materials_ior.ior; fallback when absent.
double extensionNumber(const Source& src, const tinygltf::Material& gm, const std::string& materialField,
                       const char* extension, const char* key, double fallback) {
    auto it = gm.extensions.find(extension);
    if (it == gm.extensions.end()) return fallback;
    const tinygltf::Value* v = member(it->second, key);
    return v ? finiteNumber(src, *v, materialField + ".extensions." + extension + "." + key) : fallback;
}

// glTF texture index → index into SceneDescription::textures, decoding each image once.
class TextureTable {
public:
    TextureTable(const Source& src, const tinygltf::Model& model, SceneDescription& desc)
        : src_(src), model_(model), desc_(desc), byImage_(model.images.size(), -1) {}

    int get(const tinygltf::TextureInfo& info, const std::string& field) {
        if (info.index == -1) return -1;  // texCoord other than 0 is read as 0
        checkIndex(src_, info.index, model_.textures.size(), field + ".index", "texture");
        const std::string textureField = at("textures", size_t(info.index));
        const int source = model_.textures[size_t(info.index)].source;
        if (source == -1) src_.fail(textureField + ".source", "no image (only PNG and JPEG images are supported)");
        const int image = checkIndex(src_, source, model_.images.size(), textureField + ".source", "image");
        if (byImage_[size_t(image)] < 0) {
            byImage_[size_t(image)] = int(desc_.textures.size());
            desc_.textures.push_back(decode(image));
        }
        return byImage_[size_t(image)];
    }

private:
    Texture decode(int index) {
        const tinygltf::Image& image = model_.images[size_t(index)];
        const std::string field = at("images", size_t(index));
        if (image.bufferView == -1 || !image.image.empty()) return decodeSrgbImage(src_, image, field);
        // Stored in a buffer view: tinygltf left it to us (see readModel) to check bounds first.
        size_t length = 0;
        const unsigned char* bytes = bufferViewBytes(src_, model_, image.bufferView, field + ".bufferView", &length);
        if (length == 0 || length > size_t(INT_MAX)) src_.fail(field, "image of " + std::to_string(length) + " bytes");
        tinygltf::Image decoded;
        decoded.name = image.name;
        std::string err, warn;
        if (!tinygltf::LoadImageData(&decoded, index, &err, &warn, 0, 0, bytes, int(length), nullptr))
            src_.fail(field, "cannot decode: " + err);
        return decodeSrgbImage(src_, decoded, field);
    }

    const Source& src_;
    const tinygltf::Model& model_;
    SceneDescription& desc_;
    std::vector<int> byImage_;
};

Material convert(const Source& src, const tinygltf::Material& gm, const std::string& mf, TextureTable& textures) {
    Material m;
    const tinygltf::PbrMetallicRoughness& pbr = gm.pbrMetallicRoughness;
    const std::string pf = mf + ".pbrMetallicRoughness";
    if (pbr.baseColorFactor.size() != 4)
        src.fail(pf + ".baseColorFactor", "expected 4 numbers, got " + std::to_string(pbr.baseColorFactor.size()));
    for (int c = 0; c < 3; ++c)  // alpha is ignored
        m.baseColor[c] = float(unitInterval(src, pbr.baseColorFactor[size_t(c)], pf + ".baseColorFactor"));
    m.metallic = float(unitInterval(src, pbr.metallicFactor, pf + ".metallicFactor"));
    m.roughness = float(unitInterval(src, pbr.roughnessFactor, pf + ".roughnessFactor"));
    m.baseColorTexture = textures.get(pbr.baseColorTexture, pf + ".baseColorTexture");

    Spectrum emissive;
    for (int c = 0; c < 3; ++c)  // tinygltf guarantees 3 numbers
        emissive[c] = float(unitInterval(src, gm.emissiveFactor[size_t(c)], mf + ".emissiveFactor"));
    const double strength =
        extensionNumber(src, gm, mf, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
    const std::string strengthField = mf + ".extensions.KHR_materials_emissive_strength.emissiveStrength";
    if (strength < 0) src.fail(strengthField, "negative strength " + num(strength));
    m.emission = emissive * float(strength);
    if (!isFinite(m.emission)) src.fail(strengthField, num(strength) + " is too large");
    m.emissiveTexture = textures.get(gm.emissiveTexture, mf + ".emissiveTexture");

    const double transmission = unitInterval(
        src, extensionNumber(src, gm, mf, "KHR_materials_transmission", "transmissionFactor", 0.0),
        mf + ".extensions.KHR_materials_transmission.transmissionFactor");
    const double ior = extensionNumber(src, gm, mf, "KHR_materials_ior", "ior", 1.5);
    const std::string iorField = mf + ".extensions.KHR_materials_ior.ior";
    if (!(ior >= 1)) src.fail(iorField, "ior " + num(ior) + " must be at least 1");
    if (ior > 1e6) src.fail(iorField, "ior " + num(ior) + " is too large");
    m.ior = float(ior);

    if (transmission >= 0.5)
        m.kind = MaterialKind::Dielectric;
    else
        m.kind = m.metallic > 0 ? MaterialKind::Glossy : MaterialKind::Diffuse;
    m.doubleSided = gm.doubleSided;

    // extras "transparent" (a light surface that rays cross, as Cycles' lights) and
    // "cameraVisible" (false: camera rays do not see it).
    auto flag = [&](const char* key, bool fallback) {
        const tinygltf::Value* v = member(gm.extras, key);
        if (!v) return fallback;
        if (!v->IsBool()) src.fail(mf + ".extras." + key, "expected true or false");
        return v->Get<bool>();
    };
    m.transparent = flag("transparent", false);
    m.cameraVisible = flag("cameraVisible", true);
    if (!m.cameraVisible && !m.transparent)
        src.fail(mf + ".extras.cameraVisible", "false needs \"transparent\": true (an opaque surface would hide what lies behind it)");
    if (m.transparent) m.kind = MaterialKind::Invisible;
    return m;
}

}  // namespace

double srgbToLinear(double encoded) {
    return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

Texture decodeSrgbImage(const Source& src, const tinygltf::Image& image, const std::string& field) {
    const int w = image.width, h = image.height, channels = image.component, bits = image.bits;
    if (w < 1 || h < 1 || channels < 1 || channels > 4 || (bits != 8 && bits != 16))
        src.fail(field, "unsupported image: " + std::to_string(w) + "x" + std::to_string(h) + ", " +
                            std::to_string(channels) + " channels of " + std::to_string(bits) + " bits");
    const size_t bytesPerChannel = size_t(bits / 8), pixels = size_t(w) * size_t(h);
    if (image.image.size() != pixels * size_t(channels) * bytesPerChannel)
        src.fail(field, "decoded image has " + std::to_string(image.image.size()) + " bytes, expected " +
                            std::to_string(pixels * size_t(channels) * bytesPerChannel));

    static const std::array<float, 256> table8 = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[size_t(i)] = float(srgbToLinear(i / 255.0));
        return t;
    }();
    auto channel = [&](size_t pixel, int c) -> float {
        const unsigned char* p = image.image.data() + (pixel * size_t(channels) + size_t(c)) * bytesPerChannel;
        if (bits == 8) return table8[*p];
        uint16_t v;
        std::memcpy(&v, p, 2);  // stb_image returns 16-bit samples in host byte order
        return float(srgbToLinear(v / 65535.0));
    };

    Texture t;
    t.width = w;
    t.height = h;
    t.texels.resize(pixels);
    for (size_t i = 0; i < pixels; ++i) {
        if (channels < 3) {  // grey or grey + alpha
            t.texels[i] = Spectrum(channel(i, 0));
        } else {
            t.texels[i] = Spectrum(channel(i, 0), channel(i, 1), channel(i, 2));
        }
    }
    return t;
}

void loadMaterials(const Source& src, const tinygltf::Model& model, SceneDescription& desc) {
    TextureTable textures(src, model, desc);
    for (size_t i = 0; i < model.materials.size(); ++i)
        desc.materials.push_back(convert(src, model.materials[i], at("materials", i), textures));
}

}  // namespace brume::gltf
