// The glTF scene loader: what it reads (geometry in world space, camera, lights, media,
// materials, textures) and how it fails (one-line SceneError naming file and field).
// Scenes are assembled as small .gltf files in a temporary directory.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "brume/scene/gltf_detail.h"
#include "brume/scene/gltf_loader.h"

using namespace brume;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

// PNGs written with Python's zlib and struct modules.
// 2×2 RGB, 8 bits: (255,0,0) (0,255,0) / (0,0,255) (128,64,32).
const char* const kPngRgb =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAIAAAD91JpzAAAAE0lEQVR4nGP4z8DAAMIM/xscFAAcFAPeQC/xHQAAAABJRU5ErkJggg==";
// 2×1 grey, 16 bits: 0, 32768.
const char* const kPngGrey16 =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAABEAAAAACB2fwVAAAADUlEQVR4nGNgYGhgAAABBQCBIxe6sAAAAABJRU5ErkJggg==";
// 1×1 grey + alpha, 8 bits: grey 100, alpha 7.
const char* const kPngGreyAlpha =
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAQAAAC1HAwCAAAAC0lEQVR4nGNIYQcAANIAbJYEOm4AAAAASUVORK5CYII=";

const char* const kBase64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string base64(const void* data, size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    std::string out;
    for (size_t i = 0; i < size; i += 3) {
        uint32_t v = uint32_t(p[i]) << 16;
        if (i + 1 < size) v |= uint32_t(p[i + 1]) << 8;
        if (i + 2 < size) v |= uint32_t(p[i + 2]);
        out += kBase64[(v >> 18) & 63];
        out += kBase64[(v >> 12) & 63];
        out += i + 1 < size ? kBase64[(v >> 6) & 63] : '=';
        out += i + 2 < size ? kBase64[v & 63] : '=';
    }
    return out;
}

std::vector<unsigned char> unbase64(const std::string& text) {
    std::vector<unsigned char> out;
    uint32_t bits = 0;
    int count = 0;
    for (char c : text) {
        const char* at = std::strchr(kBase64, c);
        if (c == '=' || !at) continue;
        bits = (bits << 6) | uint32_t(at - kBase64);
        if ((count += 6) >= 8) {
            count -= 8;
            out.push_back(static_cast<unsigned char>((bits >> count) & 255));
        }
    }
    return out;
}

std::string join(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& s : items) out += (out.empty() ? "" : ",") + s;
    return out;
}

std::string str(size_t i) { return std::to_string(i); }
std::string str(int i) { return std::to_string(i); }

// A glTF file under construction. Each add* takes the members of one JSON object (without
// braces) and returns its index.
struct Gltf {
    enum class Storage { Embedded, External, Glb };
    std::vector<unsigned char> bin;
    std::vector<std::string> bufferViews, accessors, meshes, nodes, materials, textures, images, cameras, lights;
    std::vector<int> roots;
    std::string media;     // the root BRUME_media object; empty for none
    std::string topLevel;  // more top-level members, each followed by a comma
    int scene = 0;         // the default scene
    Storage storage = Storage::Embedded;
    std::string externalBuffer = "buffer.bin";

    int addView(const void* data, size_t size, int stride = 0) {
        while (bin.size() % 4) bin.push_back(0);
        size_t offset = bin.size();
        const auto* p = static_cast<const unsigned char*>(data);
        bin.insert(bin.end(), p, p + size);
        bufferViews.push_back("{\"buffer\":0,\"byteOffset\":" + str(offset) + ",\"byteLength\":" + str(size) +
                              (stride ? ",\"byteStride\":" + str(stride) : "") + "}");
        return int(bufferViews.size()) - 1;
    }
    int addAccessor(int view, int componentType, size_t count, const char* type, size_t byteOffset = 0) {
        accessors.push_back("{\"bufferView\":" + str(view) + ",\"byteOffset\":" + str(byteOffset) +
                            ",\"componentType\":" + str(componentType) + ",\"count\":" + str(count) +
                            ",\"type\":\"" + type + "\"}");
        return int(accessors.size()) - 1;
    }
    template <class T>
    int addArray(const std::vector<T>& v, int componentType, int components, const char* type) {
        return addAccessor(addView(v.data(), sizeof(T) * v.size()), componentType, v.size() / size_t(components), type);
    }
    int addVec3(const std::vector<float>& v) { return addArray(v, 5126, 3, "VEC3"); }
    int addVec2(const std::vector<float>& v) { return addArray(v, 5126, 2, "VEC2"); }
    int addIndices8(const std::vector<uint8_t>& v) { return addArray(v, 5121, 1, "SCALAR"); }
    int addIndices16(const std::vector<uint16_t>& v) { return addArray(v, 5123, 1, "SCALAR"); }
    int addIndices32(const std::vector<uint32_t>& v) { return addArray(v, 5125, 1, "SCALAR"); }

    static int add(std::vector<std::string>& list, const std::string& members) {
        list.push_back("{" + members + "}");
        return int(list.size()) - 1;
    }
    int addNode(const std::string& m) { return add(nodes, m); }
    int addRoot(const std::string& m) {
        roots.push_back(addNode(m));
        return roots.back();
    }
    int addMesh(const std::string& m) { return add(meshes, m); }
    int addMaterial(const std::string& m) { return add(materials, m); }
    int addTexture(const std::string& m) { return add(textures, m); }
    int addImage(const std::string& m) { return add(images, m); }
    int addCamera(const std::string& m) { return add(cameras, m); }
    int addLight(const std::string& m) { return add(lights, m); }

    std::string json() const {
        std::ostringstream s;
        s << "{\"asset\":{\"version\":\"2.0\"}," << topLevel;
        auto array = [&](const char* name, const std::vector<std::string>& items) {
            if (!items.empty()) s << "\"" << name << "\":[" << join(items) << "],";
        };
        array("bufferViews", bufferViews);
        array("accessors", accessors);
        array("meshes", meshes);
        array("nodes", nodes);
        array("materials", materials);
        array("textures", textures);
        array("images", images);
        array("cameras", cameras);
        std::string extensions;
        if (!lights.empty()) extensions = "\"KHR_lights_punctual\":{\"lights\":[" + join(lights) + "]}";
        if (!media.empty()) extensions += (extensions.empty() ? "" : ",") + std::string("\"BRUME_media\":") + media;
        if (!extensions.empty()) s << "\"extensions\":{" << extensions << "},";
        if (!bin.empty()) {
            s << "\"buffers\":[{\"byteLength\":" << bin.size();
            if (storage == Storage::Embedded)
                s << ",\"uri\":\"data:application/octet-stream;base64," << base64(bin.data(), bin.size()) << "\"";
            else if (storage == Storage::External)
                s << ",\"uri\":\"" << externalBuffer << "\"";
            s << "}],";
        }
        std::vector<std::string> rootList;
        for (int r : roots) rootList.push_back(str(r));
        s << "\"scene\":" << scene << ",\"scenes\":[{\"nodes\":[" << join(rootList) << "]}]}";
        return s.str();
    }

    // The file as a binary glTF: header, JSON chunk, BIN chunk.
    std::string glb() {
        storage = Storage::Glb;
        std::string text = json();
        while (text.size() % 4) text += ' ';
        std::string data(bin.begin(), bin.end());
        while (data.size() % 4) data += '\0';
        std::string out = "glTF";
        auto u32 = [&](size_t v) {
            for (int i = 0; i < 4; ++i) out += char((v >> (8 * i)) & 255);
        };
        u32(2);
        u32(12 + 8 + text.size() + (data.empty() ? 0 : 8 + data.size()));
        u32(text.size());
        u32(0x4E4F534A);  // "JSON"
        out += text;
        if (!data.empty()) {
            u32(data.size());
            u32(0x004E4942);  // "BIN\0"
            out += data;
        }
        return out;
    }
};

// Node 0 is a perspective camera at the origin, the least a loadable scene needs.
Gltf withCamera() {
    Gltf g;
    g.addCamera("\"type\":\"perspective\",\"perspective\":{\"yfov\":0.8,\"znear\":0.1}");
    g.addRoot("\"camera\":0");
    return g;
}

// A mesh with one triangle (0,0,0), (1,0,0), (0,1,0) facing +z: normals, uvs, u16 indices.
int addTriangle(Gltf& g, const std::string& primitiveMembers = "", const std::string& meshMembers = "") {
    int position = g.addVec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
    int normal = g.addVec3({0, 0, 1, 0, 0, 1, 0, 0, 1});
    int uv = g.addVec2({0, 0, 1, 0, 0, 1});
    int indices = g.addIndices16({0, 1, 2});
    return g.addMesh("\"primitives\":[{\"attributes\":{\"POSITION\":" + str(position) + ",\"NORMAL\":" + str(normal) +
                     ",\"TEXCOORD_0\":" + str(uv) + "},\"indices\":" + str(indices) + primitiveMembers + "}]" +
                     meshMembers);
}

// A node with a mesh of one primitive: POSITION accessor, and indices unless -1.
void addPositionsMesh(Gltf& g, int position, int indices = -1) {
    std::string primitive = "{\"attributes\":{\"POSITION\":" + str(position) + "}";
    if (indices >= 0) primitive += ",\"indices\":" + str(indices);
    g.addRoot("\"mesh\":" + str(g.addMesh("\"primitives\":[" + primitive + "}]")));
}

class TempDir {
public:
    TempDir() {
        static int counter = 0;
        dir_ = fs::temp_directory_path() /
               ("brume_test_gltf_loader_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::create_directories(dir_);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    std::string write(const std::string& name, const std::string& content) const {
        fs::path p = dir_ / name;
        std::ofstream(p, std::ios::binary) << content;
        return p.string();
    }
    std::string write(const Gltf& g, const std::string& name = "scene.gltf") const { return write(name, g.json()); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }

private:
    fs::path dir_;
};

void checkVec(Vec3 a, Vec3 b, double eps = 1e-6) {
    INFO("got (" << a.x << ", " << a.y << ", " << a.z << "), expected (" << b.x << ", " << b.y << ", " << b.z << ")");
    CHECK(a.x == Approx(b.x).margin(eps));
    CHECK(a.y == Approx(b.y).margin(eps));
    CHECK(a.z == Approx(b.z).margin(eps));
}

// The exact sRGB EOTF, written out here independently of the loader.
double linearFromSrgb(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// Loading must fail with one line "<path>: <field>: <problem>" whose problem contains `problem`.
void requireSceneError(const std::string& path, const std::string& field, const std::string& problem) {
    INFO("loading " << path << ", expecting an error in " << field);
    try {
        loadGltf(path);
        FAIL("no SceneError");
    } catch (const SceneError& e) {
        const std::string message = e.what();
        INFO("message: " << message);
        CHECK(message.rfind(path + ": " + field + ": ", 0) == 0);
        CHECK_THAT(message, Contains(problem));
        CHECK(message.find('\n') == std::string::npos);
    }
}

void requireLoadError(const TempDir& dir, const Gltf& g, const std::string& field, const std::string& problem) {
    requireSceneError(dir.write(g), field, problem);
}

// The winding's geometric normal of triangle t.
Vec3 faceNormal(const Mesh& m, int t) {
    Vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]];
    Vec3 c = m.positions[m.indices[3 * t + 2]];
    return normalize(cross(b - a, c - a));
}

}  // namespace

TEST_CASE("a triangle with a material", "[gltf]") {
    TempDir dir;
    Gltf g = withCamera();
    g.addMaterial(
        "\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.2,0.4,0.6,0.5],\"metallicFactor\":0,"
        "\"roughnessFactor\":0.3},\"doubleSided\":true");
    g.addRoot("\"mesh\":" + str(addTriangle(g, ",\"material\":0")));
    const std::string path = dir.write(g);
    SceneDescription d = loadGltf(path);

    CHECK(d.path == path);
    REQUIRE(d.meshes.size() == 1);
    const Mesh& m = d.meshes[0];
    REQUIRE(m.positions.size() == 3);
    checkVec(m.positions[0], Vec3(0, 0, 0));
    checkVec(m.positions[1], Vec3(1, 0, 0));
    checkVec(m.positions[2], Vec3(0, 1, 0));
    REQUIRE(m.normals.size() == 3);
    for (Vec3 n : m.normals) checkVec(n, Vec3(0, 0, 1));
    CHECK(m.uvs == std::vector<float>{0, 0, 1, 0, 0, 1});
    CHECK(m.indices == std::vector<uint32_t>{0, 1, 2});
    CHECK(m.material == 0);
    CHECK(m.interiorMedium == -1);

    REQUIRE(d.materials.size() == 1);  // no fallback material needed
    const Material& mat = d.materials[0];
    CHECK(mat.kind == MaterialKind::Diffuse);
    checkVec(mat.baseColor, Vec3(0.2f, 0.4f, 0.6f));
    CHECK(mat.metallic == 0);
    CHECK(mat.roughness == Approx(0.3));
    CHECK(mat.doubleSided);
    CHECK_FALSE(mat.isEmissive());
    CHECK(mat.baseColorTexture == -1);
    CHECK(mat.emissiveTexture == -1);
    CHECK(d.lights.empty());
    CHECK(d.media.empty());
    CHECK(d.ambientMedium == -1);
    CHECK(d.textures.empty());
}

TEST_CASE("index types, unindexed primitives, strided attributes and skipped modes", "[gltf]") {
    TempDir dir;
    Gltf g = withCamera();
    // Positions and normals interleaved in one buffer view with a 24-byte stride.
    std::vector<float> interleaved = {0, 0, 0, 0, 0, 1, 2, 0, 0, 0, 0, 1, 0, 3, 0, 0, 0, 1};
    int view = g.addView(interleaved.data(), 4 * interleaved.size(), 24);
    int position = g.addAccessor(view, 5126, 3, "VEC3", 0);
    int normal = g.addAccessor(view, 5126, 3, "VEC3", 12);
    int i8 = g.addIndices8({2, 1, 0});
    int i32 = g.addIndices32({0, 1, 2, 2, 1, 0});
    std::string attributes = "\"attributes\":{\"POSITION\":" + str(position) + ",\"NORMAL\":" + str(normal) + "}";
    g.addRoot("\"mesh\":" + str(g.addMesh("\"primitives\":[{" + attributes + "},{" + attributes +
                                          ",\"indices\":" + str(i8) + "},{" + attributes + ",\"indices\":" +
                                          str(i32) + "},{" + attributes + ",\"mode\":1},{" + attributes +
                                          ",\"mode\":5}]")));
    SceneDescription d = loadGltf(dir.write(g));

    REQUIRE(d.meshes.size() == 3);  // lines and strips are skipped
    for (const Mesh& m : d.meshes) {
        REQUIRE(m.positions.size() == 3);
        checkVec(m.positions[1], Vec3(2, 0, 0));
        checkVec(m.positions[2], Vec3(0, 3, 0));
        REQUIRE(m.normals.size() == 3);
        checkVec(m.normals[2], Vec3(0, 0, 1));
        CHECK(m.uvs.empty());
        CHECK(m.material == 0);  // the fallback material
    }
    CHECK(d.meshes[0].indices == std::vector<uint32_t>{0, 1, 2});
    CHECK(d.meshes[1].indices == std::vector<uint32_t>{2, 1, 0});
    CHECK(d.meshes[2].indices == std::vector<uint32_t>{0, 1, 2, 2, 1, 0});
    CHECK(d.meshes[2].triangleCount() == 2);
    REQUIRE(d.materials.size() == 1);  // one fallback shared by all
    CHECK(d.materials[0].kind == MaterialKind::Diffuse);
    checkVec(d.materials[0].baseColor, Vec3(0.8f));
}

TEST_CASE("the node hierarchy is flattened into world space", "[gltf]") {
    TempDir dir;
    Gltf g = withCamera();
    int mesh = addTriangle(g);
    const double h = std::sqrt(0.5);
    // Parent: translate (1,2,3), scale 2. Child: 90° about +z.
    g.addRoot("\"translation\":[1,2,3],\"scale\":[2,2,2],\"children\":[2]");
    g.addNode("\"rotation\":[0,0," + std::to_string(h) + "," + std::to_string(h) + "],\"mesh\":" + str(mesh));
    // Column-major matrix: scale y by 3, translate x by 5.
    g.addRoot("\"matrix\":[1,0,0,0, 0,3,0,0, 0,0,1,0, 5,0,0,1],\"mesh\":" + str(mesh));
    SceneDescription d = loadGltf(dir.write(g));

    REQUIRE(d.meshes.size() == 2);
    const Mesh& a = d.meshes[0];
    checkVec(a.positions[0], Vec3(1, 2, 3), 1e-5);
    checkVec(a.positions[1], Vec3(1, 4, 3), 1e-5);
    checkVec(a.positions[2], Vec3(-1, 2, 3), 1e-5);
    for (Vec3 n : a.normals) checkVec(n, Vec3(0, 0, 1), 1e-5);
    CHECK(a.indices == std::vector<uint32_t>{0, 1, 2});
    const Mesh& b = d.meshes[1];
    checkVec(b.positions[0], Vec3(5, 0, 0));
    checkVec(b.positions[1], Vec3(6, 0, 0));
    checkVec(b.positions[2], Vec3(5, 3, 0));
    checkVec(faceNormal(b, 0), Vec3(0, 0, 1));
}

TEST_CASE("a mirroring node flips the winding so counter-clockwise stays the front", "[gltf]") {
    TempDir dir;
    Gltf g = withCamera();
    int mesh = addTriangle(g);
    g.addRoot("\"scale\":[-1,1,1],\"mesh\":" + str(mesh));  // mirrored
    g.addRoot("\"scale\":[-1,1,1],\"children\":[3]");         // mirrored twice: a rotation
    g.addNode("\"scale\":[1,-1,1],\"mesh\":" + str(mesh));
    // A mirror with a normal that is not along an axis of the mirror plane.
    g.addRoot("\"scale\":[1,1,-1],\"rotation\":[0.5,0.5,0.5,0.5],\"mesh\":" + str(mesh));
    SceneDescription d = loadGltf(dir.write(g));

    REQUIRE(d.meshes.size() == 3);
    const Mesh& mirrored = d.meshes[0];
    checkVec(mirrored.positions[1], Vec3(-1, 0, 0));
    CHECK(mirrored.indices == std::vector<uint32_t>{0, 2, 1});
    checkVec(mirrored.normals[0], Vec3(0, 0, 1));
    checkVec(faceNormal(mirrored, 0), Vec3(0, 0, 1));

    const Mesh& twice = d.meshes[1];
    CHECK(twice.indices == std::vector<uint32_t>{0, 1, 2});
    checkVec(twice.positions[1], Vec3(-1, 0, 0));
    checkVec(twice.positions[2], Vec3(0, -1, 0));
    checkVec(faceNormal(twice, 0), Vec3(0, 0, 1));

    // Shading normals agree with the winding's front face in every case.
    for (const Mesh& m : d.meshes)
        for (Vec3 n : m.normals) CHECK(dot(n, faceNormal(m, 0)) == Approx(1).margin(1e-5));
}

TEST_CASE("the camera is the first perspective camera depth first", "[gltf]") {
    TempDir dir;
    Gltf g;
    const double h = std::sqrt(0.5);
    g.addCamera("\"type\":\"perspective\",\"perspective\":{\"yfov\":0.7,\"aspectRatio\":1.5,\"znear\":0.1}");
    g.addCamera("\"type\":\"perspective\",\"perspective\":{\"yfov\":0.9,\"znear\":0.1}");
    g.addCamera("\"type\":\"orthographic\",\"orthographic\":{\"xmag\":1,\"ymag\":1,\"zfar\":10,\"znear\":0.1}");
    g.addNode("\"camera\":1");                 // node 0: a root visited after node 1's subtree
    g.addNode("\"children\":[3]");             // node 1
    g.addNode("\"camera\":2");                 // node 2: orthographic, ignored next to a perspective one
    g.addNode("\"translation\":[1,2,3],\"rotation\":[0," + std::to_string(h) + ",0," + std::to_string(h) +
              "],\"camera\":0");  // node 3: 90° about +y
    g.roots = {2, 1, 0};
    SceneDescription d = loadGltf(dir.write(g));

    const Camera& c = d.camera;
    CHECK(c.yfov == Approx(0.7));
    CHECK(c.aspectRatio == Approx(1.5));
    checkVec(c.position, Vec3(1, 2, 3), 1e-5);
    checkVec(c.forward, Vec3(-1, 0, 0), 1e-5);
    checkVec(c.up, Vec3(0, 1, 0), 1e-5);
    checkVec(c.right, Vec3(0, 0, -1), 1e-5);
}

TEST_CASE("a camera under non-uniform scale gets an orthonormal frame", "[gltf]") {
    TempDir dir;
    Gltf g;
    g.addCamera("\"type\":\"perspective\",\"perspective\":{\"yfov\":0.5,\"znear\":0.1}");
    // 30° about +x under a parent that stretches y by 3.
    const double s = std::sin(kPi / 12), c = std::cos(kPi / 12);
    g.addRoot("\"scale\":[1,3,1],\"children\":[1]");
    g.addNode("\"rotation\":[" + std::to_string(s) + ",0,0," + std::to_string(c) + "],\"camera\":0");
    SceneDescription d = loadGltf(dir.write(g));

    const Camera& cam = d.camera;
    CHECK(cam.aspectRatio == 0);  // absent
    checkVec(cam.forward, normalize(Vec3(0, 1.5f, -std::sqrt(3.0f) / 2)), 1e-5);
    CHECK(length(cam.up) == Approx(1));
    CHECK(length(cam.right) == Approx(1));
    CHECK(dot(cam.up, cam.forward) == Approx(0).margin(1e-6));
    checkVec(cam.right, cross(cam.forward, cam.up));
    checkVec(cam.right, Vec3(1, 0, 0), 1e-5);
    CHECK(cam.up.y > 0);
}

TEST_CASE("punctual lights in radiometric units", "[gltf]") {
    TempDir dir;
    Gltf g = withCamera();
    const double h = std::sqrt(0.5);
    g.addLight("\"type\":\"point\",\"color\":[1,0.5,0.25],\"intensity\":8");
    g.addLight("\"type\":\"spot\",\"intensity\":3,\"spot\":{\"innerConeAngle\":0.2,\"outerConeAngle\":0.6}");
    g.addLight("\"type\":\"point\",\"intensity\":5,\"extras\":{\"radius\":0.25}");
    g.addLight("\"type\":\"directional\"");
    g.addLight("\"type\":\"spot\",\"intensity\":2,\"spot\":{}");
    g.addLight("\"type\":\"point\",\"intensity\":1,\"extras\":{\"radius\":0}");
    auto lightNode = [&](const std::string& members, int light) {
        g.addRoot(members + "\"extensions\":{\"KHR_lights_punctual\":{\"light\":" + str(light) + "}}");
    };
    lightNode("\"translation\":[0,3,0],", 0);
    lightNode("\"translation\":[1,2,3],\"rotation\":[" + std::to_string(-h) + ",0,0," + std::to_string(h) + "],", 1);
    lightNode("\"translation\":[2,0,0],\"scale\":[10,10,10],", 2);
    lightNode("", 3);
    lightNode("", 4);
    lightNode("", 5);
    SceneDescription d = loadGltf(dir.write(g));

    REQUIRE(d.lights.size() == 6);
    const Light& point = d.lights[0];
    CHECK(point.kind == LightKind::Point);
    checkVec(point.position, Vec3(0, 3, 0));
    checkVec(point.intensity, Vec3(8, 4, 2));  // W/sr: no 683 lm/W

    const Light& spot = d.lights[1];
    CHECK(spot.kind == LightKind::Spot);
    checkVec(spot.position, Vec3(1, 2, 3), 1e-5);
    checkVec(spot.direction, Vec3(0, -1, 0), 1e-5);
    checkVec(spot.intensity, Vec3(3));
    CHECK(spot.cosInner == Approx(std::cos(0.2)));
    CHECK(spot.cosOuter == Approx(std::cos(0.6)));

    const Light& sphere = d.lights[2];
    CHECK(sphere.kind == LightKind::Sphere);
    CHECK(sphere.radius == Approx(0.25));  // not scaled by the node
    checkVec(sphere.position, Vec3(2, 0, 0));
    checkVec(sphere.intensity, Vec3(5));

    const Light& sun = d.lights[3];
    CHECK(sun.kind == LightKind::Directional);
    checkVec(sun.intensity, Vec3(1));  // color and intensity default to 1
    checkVec(sun.direction, Vec3(0, 0, -1));

    const Light& defaultCone = d.lights[4];
    CHECK(defaultCone.kind == LightKind::Spot);
    CHECK(defaultCone.cosInner == Approx(1));
    CHECK(defaultCone.cosOuter == Approx(std::cos(kPi / 4)));

    CHECK(d.lights[5].kind == LightKind::Point);  // radius 0 is a point
}

TEST_CASE("media: coefficients, anisotropy, ambient and interiors", "[gltf]") {
    TempDir dir;
    Gltf g = withCamera();
    g.media = "{\"media\":[{\"name\":\"fog\",\"scattering\":0.5,\"absorption\":[0.1,0.2,0.3],\"anisotropy\":-0.3},"
              "{\"name\":\"ink\",\"absorption\":2}],\"ambient\":0}";
    g.addMaterial("\"pbrMetallicRoughness\":{\"metallicFactor\":0}");
    int boundary = addTriangle(g, "", ",\"extensions\":{\"BRUME_media\":{\"interior\":1}}");
    int plain = addTriangle(g);
    int glass = addTriangle(g, ",\"material\":0", ",\"extensions\":{\"BRUME_media\":{\"interior\":1}}");
    for (int mesh : {boundary, plain, boundary, plain, glass}) g.addRoot("\"mesh\":" + str(mesh));
    SceneDescription d = loadGltf(dir.write(g));

    REQUIRE(d.media.size() == 2);
    CHECK(d.media[0].name == "fog");
    checkVec(d.media[0].sigmaS, Vec3(0.5f));
    checkVec(d.media[0].sigmaA, Vec3(0.1f, 0.2f, 0.3f));
    CHECK(d.media[0].g == Approx(-0.3));
    CHECK(d.media[1].name == "ink");
    checkVec(d.media[1].sigmaS, Vec3(0));
    checkVec(d.media[1].sigmaA, Vec3(2));
    CHECK(d.media[1].g == 0);
    CHECK(d.ambientMedium == 0);

    REQUIRE(d.meshes.size() == 5);
    REQUIRE(d.materials.size() == 3);  // the glTF one, then one Invisible and one default, shared
    const int invisible = d.meshes[0].material, fallback = d.meshes[1].material;
    CHECK(d.materials[size_t(invisible)].kind == MaterialKind::Invisible);
    CHECK(d.materials[size_t(fallback)].kind == MaterialKind::Diffuse);
    checkVec(d.materials[size_t(fallback)].baseColor, Vec3(0.8f));
    CHECK(d.meshes[0].interiorMedium == 1);
    CHECK(d.meshes[1].interiorMedium == -1);
    CHECK(d.meshes[2].material == invisible);
    CHECK(d.meshes[3].material == fallback);
    CHECK(d.meshes[4].material == 0);  // a boundary with a material keeps it
    CHECK(d.meshes[4].interiorMedium == 1);
}

TEST_CASE("media without ambient leave vacuum outside", "[gltf]") {
    TempDir dir;
    Gltf g = withCamera();
    g.media = "{\"media\":[{\"scattering\":[1,2,3]}]}";
    SceneDescription d = loadGltf(dir.write(g));
    REQUIRE(d.media.size() == 1);
    checkVec(d.media[0].sigmaS, Vec3(1, 2, 3));
    checkVec(d.media[0].sigmaA, Vec3(0));
    CHECK(d.ambientMedium == -1);
}

TEST_CASE("material kinds, emission and defaults", "[gltf]") {
    TempDir dir;
    Gltf g = withCamera();
    g.topLevel = "\"extensionsRequired\":[\"KHR_lights_punctual\",\"KHR_materials_emissive_strength\","
                 "\"KHR_materials_transmission\",\"KHR_materials_ior\",\"BRUME_media\"],";
    g.addMaterial("\"name\":\"defaults\"");
    g.addMaterial(
        "\"emissiveFactor\":[1,0.5,0],\"pbrMetallicRoughness\":{\"metallicFactor\":0},"
        "\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":4}}");
    g.addMaterial(
        "\"extensions\":{\"KHR_materials_transmission\":{\"transmissionFactor\":1},"
        "\"KHR_materials_ior\":{\"ior\":1.33}}");
    g.addMaterial(
        "\"pbrMetallicRoughness\":{\"metallicFactor\":0.5,\"roughnessFactor\":0.2},"
        "\"extensions\":{\"KHR_materials_transmission\":{\"transmissionFactor\":0.4}}");
    g.addMaterial("\"extensions\":{\"KHR_materials_transmission\":{\"transmissionFactor\":0.5}}");
    g.addMaterial("\"emissiveFactor\":[0.5,0.5,0.5]");
    SceneDescription d = loadGltf(dir.write(g));

    REQUIRE(d.materials.size() == 6);
    const Material& defaults = d.materials[0];
    CHECK(defaults.kind == MaterialKind::Glossy);  // glTF's metallicFactor defaults to 1
    CHECK(defaults.metallic == 1);
    CHECK(defaults.roughness == 1);
    checkVec(defaults.baseColor, Vec3(1));
    CHECK_FALSE(defaults.isEmissive());
    CHECK_FALSE(defaults.doubleSided);

    const Material& emitter = d.materials[1];
    CHECK(emitter.kind == MaterialKind::Diffuse);
    checkVec(emitter.emission, Vec3(4, 2, 0));

    const Material& glass = d.materials[2];
    CHECK(glass.kind == MaterialKind::Dielectric);
    CHECK(glass.ior == Approx(1.33));

    const Material& glossy = d.materials[3];
    CHECK(glossy.kind == MaterialKind::Glossy);
    CHECK(glossy.metallic == Approx(0.5));
    CHECK(glossy.roughness == Approx(0.2));
    CHECK(glossy.ior == Approx(1.5));

    CHECK(d.materials[4].kind == MaterialKind::Dielectric);
    CHECK(d.materials[4].ior == Approx(1.5));
    checkVec(d.materials[5].emission, Vec3(0.5f));  // strength defaults to 1
}

TEST_CASE("textures are decoded from sRGB to linear RGB", "[gltf]") {
    TempDir dir;
    Gltf g = withCamera();
    std::vector<unsigned char> png = unbase64(kPngRgb);
    int pngView = g.addView(png.data(), png.size());
    g.addImage("\"uri\":\"data:image/png;base64," + std::string(kPngRgb) + "\"");
    g.addImage("\"uri\":\"data:image/png;base64," + std::string(kPngGrey16) + "\"");
    g.addImage("\"uri\":\"data:image/png;base64," + std::string(kPngGreyAlpha) + "\"");
    g.addImage("\"bufferView\":" + str(pngView) + ",\"mimeType\":\"image/png\"");
    for (int image : {0, 1, 2, 3, 0}) g.addTexture("\"source\":" + str(image));
    g.addMaterial("\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}},\"emissiveFactor\":[1,1,1],"
                  "\"emissiveTexture\":{\"index\":4}");
    g.addMaterial("\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":1,\"texCoord\":1}}");
    g.addMaterial("\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":2}}");
    g.addMaterial("\"emissiveTexture\":{\"index\":3}");
    SceneDescription d = loadGltf(dir.write(g));

    REQUIRE(d.materials.size() == 4);
    REQUIRE(d.textures.size() == 4);  // textures 0 and 4 share image 0
    const Material& m0 = d.materials[0];
    REQUIRE(m0.baseColorTexture >= 0);
    CHECK(m0.emissiveTexture == m0.baseColorTexture);
    const Texture& rgb = d.textures[size_t(m0.baseColorTexture)];
    REQUIRE(rgb.width == 2);
    REQUIRE(rgb.height == 2);
    REQUIRE(rgb.texels.size() == 4);
    checkVec(rgb.texels[0], Vec3(1, 0, 0));  // row 0 is the top row
    checkVec(rgb.texels[1], Vec3(0, 1, 0));
    checkVec(rgb.texels[2], Vec3(0, 0, 1));
    checkVec(rgb.texels[3], Vec3(float(linearFromSrgb(128 / 255.0)), float(linearFromSrgb(64 / 255.0)),
                                 float(linearFromSrgb(32 / 255.0))));
    CHECK(rgb.texels[3].x == Approx(0.2158605).epsilon(1e-5));  // not 128/255, not (128/255)^2.2

    REQUIRE(d.materials[1].baseColorTexture >= 0);
    const Texture& grey16 = d.textures[size_t(d.materials[1].baseColorTexture)];
    REQUIRE(grey16.texels.size() == 2);
    CHECK(grey16.width == 2);
    CHECK(grey16.height == 1);
    checkVec(grey16.texels[0], Vec3(0));
    checkVec(grey16.texels[1], Vec3(float(linearFromSrgb(32768 / 65535.0))), 1e-7);

    REQUIRE(d.materials[2].baseColorTexture >= 0);
    const Texture& greyAlpha = d.textures[size_t(d.materials[2].baseColorTexture)];
    REQUIRE(greyAlpha.texels.size() == 1);
    checkVec(greyAlpha.texels[0], Vec3(float(linearFromSrgb(100 / 255.0))));  // alpha dropped

    REQUIRE(d.materials[3].emissiveTexture >= 0);
    const Texture& fromBufferView = d.textures[size_t(d.materials[3].emissiveTexture)];
    REQUIRE(fromBufferView.texels.size() == 4);
    for (size_t i = 0; i < 4; ++i) checkVec(fromBufferView.texels[i], rgb.texels[i]);
}

TEST_CASE("srgbToLinear is the exact sRGB curve", "[gltf]") {
    CHECK(gltf::srgbToLinear(0) == 0);
    CHECK(gltf::srgbToLinear(1) == Approx(1));
    CHECK(gltf::srgbToLinear(0.04045) == Approx(0.04045 / 12.92));
    CHECK(gltf::srgbToLinear(0.5) == Approx(0.21404114).epsilon(1e-7));
}

// A camera and one triangle whose buffer is the file triangle.bin, written into dir.
Gltf triangleWithExternalBuffer(const TempDir& dir) {
    Gltf g = withCamera();
    g.addRoot("\"translation\":[0,0,-1],\"mesh\":" + str(addTriangle(g)));
    g.storage = Gltf::Storage::External;
    g.externalBuffer = "triangle.bin";
    dir.write("triangle.bin", std::string(g.bin.begin(), g.bin.end()));
    return g;
}

TEST_CASE("external buffers and binary glTF", "[gltf]") {
    TempDir dir;
    Gltf g = triangleWithExternalBuffer(dir);
    SceneDescription external = loadGltf(dir.write(g));
    SceneDescription binary = loadGltf(dir.write("scene.glb", g.glb()));

    for (const SceneDescription* d : {&external, &binary}) {
        REQUIRE(d->meshes.size() == 1);
        REQUIRE(d->meshes[0].positions.size() == 3);
        checkVec(d->meshes[0].positions[2], Vec3(0, 1, -1));
        CHECK(d->meshes[0].uvs == std::vector<float>{0, 0, 1, 0, 0, 1});
    }
}

// The files a scene was read from (SceneDescription::files), whose contents are its identity
// for checkpoints and MPI ranks: the scene file first, then buffers and images named by URI
// (%-escapes decoded, as tinygltf opens them), each once; embedded ones are not files.
TEST_CASE("a scene lists every file it reads, each once", "[gltf]") {
    TempDir dir;
    Gltf g = triangleWithExternalBuffer(dir);
    std::vector<unsigned char> png = unbase64(kPngRgb);
    dir.write("base colour.png", std::string(png.begin(), png.end()));
    g.addImage("\"uri\":\"base%20colour.png\"");
    g.addImage("\"uri\":\"base%20colour.png\"");  // the same file twice
    g.addImage("\"uri\":\"data:image/png;base64," + std::string(kPngRgb) + "\"");
    const std::string scene = dir.write(g);
    const SceneDescription d = loadGltf(scene);
    CHECK(d.files == std::vector<std::string>{scene, dir.path("triangle.bin"), dir.path("base colour.png")});
    const std::string glb = dir.write("scene.glb", g.glb());  // (it holds its buffer)
    CHECK(loadGltf(glb).files == std::vector<std::string>{glb, dir.path("base colour.png")});

    // A density grid, beside the scene file in tests/data.
    const std::string gradient = std::string(BRUME_TEST_DATA) + "/single_gradient.gltf";
    CHECK(loadGltf(gradient).files == std::vector<std::string>{gradient, std::string(BRUME_TEST_DATA) + "/gradient.vdb"});
}

TEST_CASE("the example in docs/scene-format.md loads and matches the fixture", "[gltf]") {
    const std::string fixture = std::string(BRUME_TEST_DATA) + "/loader/example.gltf";
    SceneDescription d = loadGltf(fixture);

    checkVec(d.camera.position, Vec3(0, 1, 4));
    checkVec(d.camera.forward, Vec3(0, 0, -1));
    CHECK(d.camera.yfov == Approx(0.6));
    CHECK(d.camera.aspectRatio == Approx(1.5));
    REQUIRE(d.meshes.size() == 1);
    CHECK(d.meshes[0].positions.size() == 4);
    CHECK(d.meshes[0].triangleCount() == 2);
    for (int t = 0; t < 2; ++t) checkVec(faceNormal(d.meshes[0], t), Vec3(0, 1, 0));
    REQUIRE(d.materials.size() == 1);
    CHECK(d.materials[0].kind == MaterialKind::Diffuse);
    checkVec(d.materials[0].baseColor, Vec3(0.7f));
    REQUIRE(d.lights.size() == 1);
    CHECK(d.lights[0].kind == LightKind::Spot);
    checkVec(d.lights[0].position, Vec3(0, 3, 0));
    checkVec(d.lights[0].direction, Vec3(0, -1, 0), 1e-6);
    checkVec(d.lights[0].intensity, Vec3(50, 45, 40), 1e-4);
    REQUIRE(d.media.size() == 1);
    CHECK(d.media[0].name == "fog");
    checkVec(d.media[0].sigmaS, Vec3(0.05f));
    checkVec(d.media[0].sigmaA, Vec3(0.01f, 0.01f, 0.02f));
    CHECK(d.media[0].g == Approx(0.6));
    CHECK(d.ambientMedium == 0);

    // The documentation shows the fixture verbatim, in the code block after the marker.
    auto slurp = [](const std::string& path) {
        std::ifstream f(path, std::ios::binary);
        std::ostringstream s;
        s << f.rdbuf();
        return s.str();
    };
    const std::string doc = slurp(std::string(BRUME_TEST_DATA) + "/../../docs/scene-format.md");
    const std::string marker = "<!-- tests/data/loader/example.gltf -->\n```json\n";
    size_t begin = doc.find(marker);
    REQUIRE(begin != std::string::npos);
    begin += marker.size();
    size_t end = doc.find("```", begin);
    REQUIRE(end != std::string::npos);
    CHECK(doc.substr(begin, end - begin) == slurp(fixture));
}

// --- Errors ------------------------------------------------------------------------------

TEST_CASE("files that cannot be read", "[gltf][errors]") {
    TempDir dir;
    requireSceneError(dir.path("nothere.gltf"), "file", "cannot open");
    requireSceneError(dir.write("scene.obj", "o cube\n"), "file", "unsupported file extension '.obj'");
    requireSceneError(dir.write("scene", "{}"), "file", "no file extension");
    requireSceneError(dir.write("broken.gltf", "{\"asset\":{\"version\":\"2.0\"},\"nodes\":[{\"mesh\":0}"), "JSON",
                      "parse error");
    // JSON has no NaN or infinity; a number too large for a double is a parse error.
    requireSceneError(dir.write("huge.gltf", "{\"asset\":{\"version\":\"2.0\"},\"extensions\":{\"BRUME_media\":"
                                             "{\"media\":[{\"scattering\":1e999}]}}}"),
                      "JSON", "1e999");

    Gltf g = withCamera();
    g.addRoot("\"mesh\":" + str(addTriangle(g)));
    std::string glb = g.glb();
    requireSceneError(dir.write("half.glb", glb.substr(0, glb.size() / 2)), "GLB", "truncated");
    requireSceneError(dir.write("tiny.glb", glb.substr(0, 8)), "GLB", "truncated");
    requireSceneError(dir.write("json.glb", g.json()), "GLB", "not a GLB file");
}

TEST_CASE("missing external buffers and images", "[gltf][errors]") {
    TempDir dir;
    Gltf g = withCamera();
    g.addRoot("\"mesh\":" + str(addTriangle(g)));
    g.storage = Gltf::Storage::External;
    g.externalBuffer = "brume_missing_buffer.bin";
    requireLoadError(dir, g, "buffers", "brume_missing_buffer.bin");

    Gltf h = withCamera();
    h.addImage("\"uri\":\"brume_missing_image.png\"");
    h.addTexture("\"source\":0");
    h.addMaterial("\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}");
    requireLoadError(dir, h, "images[0].uri", "brume_missing_image.png");
}

TEST_CASE("unsupported required extensions", "[gltf][errors]") {
    TempDir dir;
    Gltf g = withCamera();
    g.topLevel = "\"extensionsUsed\":[\"KHR_texture_transform\",\"EXT_whatever\"],"
                 "\"extensionsRequired\":[\"KHR_lights_punctual\",\"KHR_texture_transform\"],";
    requireLoadError(dir, g, "extensionsRequired[1]", "'KHR_texture_transform' is not supported");
    g.topLevel = "\"extensionsUsed\":[\"EXT_whatever\"],\"extensionsRequired\":[\"EXT_whatever\"],";
    requireLoadError(dir, g, "extensionsRequired[0]", "EXT_whatever");
    g.topLevel = "\"extensionsUsed\":[\"EXT_whatever\"],";  // used but not required: fine
    CHECK_NOTHROW(loadGltf(dir.write(g)));
}

TEST_CASE("invalid media", "[gltf][errors]") {
    TempDir dir;
    Gltf g = withCamera();
    const std::string m0 = "extensions.BRUME_media.media[0]";
    g.media = "{\"media\":[{\"scattering\":-1}]}";
    requireLoadError(dir, g, m0 + ".scattering", "negative coefficient -1");
    g.media = "{\"media\":[{\"absorption\":[0.1,-2,0]}]}";
    requireLoadError(dir, g, m0 + ".absorption", "negative coefficient -2");
    g.media = "{\"media\":[{\"absorption\":[0.1,0.2]}]}";
    requireLoadError(dir, g, m0 + ".absorption", "3 numbers");
    g.media = "{\"media\":[{\"scattering\":\"thick\"}]}";
    requireLoadError(dir, g, m0 + ".scattering", "expected a number");
    g.media = "{\"media\":[{\"anisotropy\":1}]}";
    requireLoadError(dir, g, m0 + ".anisotropy", "|g| < 1");
    g.media = "{\"media\":[{\"name\":\"a\"},{\"anisotropy\":-1.5}]}";
    requireLoadError(dir, g, "extensions.BRUME_media.media[1].anisotropy", "|g| < 1");
    g.media = "{\"media\":[{\"scattering\":1}],\"ambient\":1}";
    requireLoadError(dir, g, "extensions.BRUME_media.ambient", "medium 1 out of range");
    g.media = "{\"media\":[{\"scattering\":1}],\"ambient\":-1}";
    requireLoadError(dir, g, "extensions.BRUME_media.ambient", "medium -1 out of range");
    g.media = "{\"ambient\":0.5}";
    requireLoadError(dir, g, "extensions.BRUME_media.ambient", "integer");

    g.media = "{\"media\":[{\"scattering\":1}]}";
    g.addRoot("\"mesh\":" + str(addTriangle(g, "", ",\"extensions\":{\"BRUME_media\":{\"interior\":1}}")));
    requireLoadError(dir, g, "meshes[0].extensions.BRUME_media.interior", "medium 1 out of range");
}

TEST_CASE("non-finite media values are rejected", "[gltf][errors]") {
    // JSON cannot carry NaN, so feed the parser tinygltf values directly.
    const gltf::Source src{"values.gltf"};
    auto mediumWith = [](const char* key, tinygltf::Value value) {
        tinygltf::Value::Object medium{{key, std::move(value)}};
        tinygltf::Value::Array media{tinygltf::Value(medium)};
        return tinygltf::Value(tinygltf::Value::Object{{"media", tinygltf::Value(media)}});
    };
    auto requireError = [&](const tinygltf::Value& ext, const std::string& expected) {
        SceneDescription d;
        try {
            gltf::parseMedia(src, ext, d);
            FAIL("no SceneError");
        } catch (const SceneError& e) {
            CHECK_THAT(std::string(e.what()), Contains(expected));
        }
    };
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    requireError(mediumWith("scattering", tinygltf::Value(nan)),
                 "values.gltf: extensions.BRUME_media.media[0].scattering: non-finite coefficient nan");
    tinygltf::Value::Array rgb{tinygltf::Value(0.1), tinygltf::Value(inf), tinygltf::Value(0.1)};
    requireError(mediumWith("absorption", tinygltf::Value(rgb)),
                 "values.gltf: extensions.BRUME_media.media[0].absorption: non-finite coefficient inf");
    requireError(mediumWith("anisotropy", tinygltf::Value(nan)),
                 "values.gltf: extensions.BRUME_media.media[0].anisotropy: non-finite");

    SceneDescription ok;
    gltf::parseMedia(src, mediumWith("scattering", tinygltf::Value(0.25)), ok);
    REQUIRE(ok.media.size() == 1);
    checkVec(ok.media[0].sigmaS, Vec3(0.25f));
}

TEST_CASE("indices out of range", "[gltf][errors]") {
    TempDir dir;
    {
        Gltf g = withCamera();
        g.addRoot("\"mesh\":" + str(g.addMesh("\"primitives\":[{\"attributes\":{\"POSITION\":9}}]")));
        requireLoadError(dir, g, "meshes[0].primitives[0].attributes.POSITION", "accessor 9 out of range");
    }
    {
        Gltf g = withCamera();
        g.addRoot("\"children\":[5]");
        requireLoadError(dir, g, "nodes[1].children[0]", "node 5 out of range");
    }
    {
        Gltf g = withCamera();
        g.roots.push_back(4);
        requireLoadError(dir, g, "scenes[0].nodes[1]", "node 4 out of range");
    }
    {
        Gltf g = withCamera();
        g.addRoot("\"mesh\":3");
        requireLoadError(dir, g, "nodes[1].mesh", "mesh 3 out of range");
        g.nodes[1] = "{\"mesh\":-2}";
        requireLoadError(dir, g, "nodes[1].mesh", "mesh -2 out of range");
    }
    {
        Gltf g = withCamera();
        g.addRoot("\"camera\":2");
        requireLoadError(dir, g, "nodes[1].camera", "camera 2 out of range");
    }
    {
        Gltf g = withCamera();
        g.addRoot("\"mesh\":" + str(addTriangle(g, ",\"material\":1")));
        requireLoadError(dir, g, "meshes[0].primitives[0].material", "material 1 out of range");
    }
    {
        Gltf g = withCamera();
        g.addLight("\"type\":\"point\"");
        g.addRoot("\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}");
        requireLoadError(dir, g, "nodes[1].extensions.KHR_lights_punctual.light", "light 1 out of range");
    }
    {
        Gltf g = withCamera();
        g.addMaterial("\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}");
        requireLoadError(dir, g, "materials[0].pbrMetallicRoughness.baseColorTexture.index", "texture 0 out of range");
        g.addTexture("\"source\":2");
        requireLoadError(dir, g, "textures[0].source", "image 2 out of range");
    }
    {
        Gltf g = withCamera();
        int mesh = addTriangle(g);
        g.addRoot("\"mesh\":" + str(mesh));
        g.accessors[0] = "{\"bufferView\":7,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}";
        requireLoadError(dir, g, "accessors[0].bufferView", "bufferView 7 out of range");
        g.accessors[0] = "{\"bufferView\":0,\"byteOffset\":4,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}";
        requireLoadError(dir, g, "accessors[0]", "do not fit");
        g.accessors[0] = "{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}";
        g.bufferViews[0] = "{\"buffer\":1,\"byteLength\":36}";
        requireLoadError(dir, g, "bufferViews[0].buffer", "buffer 1 out of range");
        g.bufferViews[0] = "{\"buffer\":0,\"byteOffset\":100,\"byteLength\":36}";
        requireLoadError(dir, g, "bufferViews[0]", "exceeds");
    }
    {
        Gltf g = withCamera();
        int position = g.addVec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
        int indices = g.addIndices16({0, 1, 3});
        addPositionsMesh(g, position, indices);
        requireLoadError(dir, g, "meshes[0].primitives[0].indices", "is 3, but there are only 3 vertices");
    }
    {
        Gltf g = withCamera();
        g.scene = 3;
        requireLoadError(dir, g, "scene", "scene 3 out of range");
    }
}

TEST_CASE("invalid geometry", "[gltf][errors]") {
    TempDir dir;
    {
        Gltf g = withCamera();
        int position = g.addVec3({0, 0, 0, std::nanf(""), 0, 0, 0, 1, 0});
        addPositionsMesh(g, position);
        requireLoadError(dir, g, "accessors[0]", "element 1 component 0 is nan");
        requireLoadError(dir, g, "accessors[0]", "meshes[0].primitives[0].attributes.POSITION");
    }
    {
        Gltf g = withCamera();
        int position = g.addVec2({0, 0, 1, 0, 0, 1});
        addPositionsMesh(g, position);
        requireLoadError(dir, g, "accessors[0].type", "VEC2 where VEC3 is needed");
    }
    {
        Gltf g = withCamera();
        int position = g.addVec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
        int indices = g.addAccessor(g.addView(std::vector<float>{0, 1, 2}.data(), 12), 5126, 3, "SCALAR");
        addPositionsMesh(g, position, indices);
        requireLoadError(dir, g, "accessors[1].componentType", "FLOAT where UNSIGNED_BYTE");
    }
    {
        Gltf g = withCamera();
        int position = g.addVec3({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
        addPositionsMesh(g, position);
        requireLoadError(dir, g, "meshes[0].primitives[0].attributes.POSITION", "whole triangles");
    }
    {
        Gltf g = withCamera();
        g.addRoot("\"mesh\":" + str(addTriangle(g)));
        g.nodes[1] = "{\"mesh\":0,\"translation\":[1,2]}";
        requireLoadError(dir, g, "nodes[1].translation", "expected 3 numbers");
    }
}

TEST_CASE("cyclic node graphs", "[gltf][errors]") {
    TempDir dir;
    Gltf g = withCamera();
    g.addRoot("\"children\":[2]");
    g.addNode("\"children\":[3]");
    g.addNode("\"children\":[1]");
    requireLoadError(dir, g, "nodes[3].children[0]",
                     "cycle in the node hierarchy: node 1 -> node 2 -> node 3 -> node 1");

    Gltf self = withCamera();
    self.addRoot("\"children\":[1]");
    requireLoadError(dir, self, "nodes[1].children[0]", "cycle");

    // The same node under two parents is not a cycle: it is placed twice.
    Gltf shared = withCamera();
    int mesh = addTriangle(shared);
    shared.addRoot("\"children\":[3]");
    shared.addRoot("\"translation\":[0,0,5],\"children\":[3]");
    shared.addNode("\"mesh\":" + str(mesh));
    SceneDescription d = loadGltf(dir.write(shared));
    REQUIRE(d.meshes.size() == 2);
    checkVec(d.meshes[1].positions[0], Vec3(0, 0, 5));
}

TEST_CASE("cameras brume cannot use", "[gltf][errors]") {
    TempDir dir;
    Gltf none;
    none.addRoot("\"mesh\":" + str(addTriangle(none)));
    requireLoadError(dir, none, "cameras", "no perspective camera");

    Gltf unused = none;  // a camera no node refers to does not count
    unused.addCamera("\"type\":\"perspective\",\"perspective\":{\"yfov\":0.8,\"znear\":0.1}");
    requireLoadError(dir, unused, "cameras", "no perspective camera");

    Gltf ortho;
    ortho.addCamera("\"type\":\"orthographic\",\"orthographic\":{\"xmag\":1,\"ymag\":1,\"zfar\":10,\"znear\":0.1}");
    ortho.addRoot("\"camera\":0");
    requireLoadError(dir, ortho, "cameras[0].type", "orthographic cameras are not supported");
}

TEST_CASE("invalid lights and materials", "[gltf][errors]") {
    TempDir dir;
    const std::string l0 = "extensions.KHR_lights_punctual.lights[0]";
    auto withLight = [](const std::string& light) {
        Gltf g = withCamera();
        g.addLight(light);
        g.addRoot("\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}");
        return g;
    };
    requireLoadError(dir, withLight("\"type\":\"point\",\"intensity\":-2"), l0 + ".intensity", "negative intensity -2");
    requireLoadError(dir, withLight("\"type\":\"point\",\"color\":[1,-0.5,1]"), l0 + ".color", "negative color");
    requireLoadError(dir, withLight("\"type\":\"spot\",\"spot\":{\"innerConeAngle\":0.6,\"outerConeAngle\":0.5}"),
                     l0 + ".spot", "innerConeAngle < outerConeAngle");
    requireLoadError(dir, withLight("\"type\":\"spot\",\"spot\":{\"outerConeAngle\":2}"), l0 + ".spot", "pi/2");
    requireLoadError(dir, withLight("\"type\":\"point\",\"extras\":{\"radius\":-1}"), l0 + ".extras.radius",
                     "negative radius");
    requireLoadError(dir, withLight("\"type\":\"area\""), l0 + ".type", "unknown light type 'area'");

    Gltf g = withCamera();
    g.addMaterial("\"pbrMetallicRoughness\":{\"baseColorFactor\":[1.5,0,0,1]}");
    requireLoadError(dir, g, "materials[0].pbrMetallicRoughness.baseColorFactor", "1.5 is not in [0, 1]");
    g.materials[0] = "{\"extensions\":{\"KHR_materials_ior\":{\"ior\":0.5}}}";
    requireLoadError(dir, g, "materials[0].extensions.KHR_materials_ior.ior", "at least 1");
    g.materials[0] = "{\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":-1}}}";
    requireLoadError(dir, g, "materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength", "negative");
}
