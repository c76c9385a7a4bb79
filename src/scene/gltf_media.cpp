// glTF loader: the BRUME_media extension (homogeneous media, the ambient medium, and the
// medium a closed mesh encloses).
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "brume/scene/gltf_detail.h"
#include "brume/scene/vdb_file.h"

namespace brume::gltf {

namespace {

float checkedCoefficient(const Source& src, double d, const std::string& field) {
    if (!std::isfinite(d)) src.fail(field, "non-finite coefficient " + num(d));
    if (d < 0) src.fail(field, "negative coefficient " + num(d));
    if (d > double(std::numeric_limits<float>::max())) src.fail(field, "coefficient " + num(d) + " is too large");
    return float(d);
}

// A coefficient in 1/m: a number (grey) or [r, g, b]; absent = 0.
Spectrum coefficient(const Source& src, const tinygltf::Value* v, const std::string& field) {
    if (!v) return Spectrum(0.0f);
    if (v->IsNumber()) return Spectrum(checkedCoefficient(src, v->GetNumberAsDouble(), field));
    if (!v->IsArray() || v->ArrayLen() != 3) src.fail(field, "expected a number or an array of 3 numbers [1/m]");
    Spectrum s;
    for (int c = 0; c < 3; ++c) {
        const tinygltf::Value& e = v->Get(c);
        if (!e.IsNumber()) src.fail(field, "expected a number or an array of 3 numbers [1/m]");
        s[c] = checkedCoefficient(src, e.GetNumberAsDouble(), field);
    }
    return s;
}

// The limit on a grid medium's density: the optical depth across one voxel (the largest
// extinction coefficient × scale × the largest voxel value × the voxel's longest edge in
// world units, the grid placed by `node`) is at most kMaxVoxelOpticalDepth. Beyond it the
// medium is opaque within 1/10000 of a voxel, finer than any grid resolves; tracking would
// take that many steps per voxel, and its float distances would stop advancing. Refused,
// naming the file and grid.
constexpr double kMaxVoxelOpticalDepth = 1e4;

void checkOpticalDepth(const Source& src, const Medium& medium, const Mat4& node, const std::string& field) {
    const Mat4 toWorld = node * medium.density.indexToWorld;
    double edge = 0;
    for (Vec3 axis : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}) edge = std::max(edge, double(length(toWorld.vector(axis))));
    const Spectrum k = medium.sigmaT();
    const double tau = double(std::max(k.x, std::max(k.y, k.z))) * medium.density.scale * medium.density.grid->maxValue * edge;
    if (!(tau <= kMaxVoxelOpticalDepth))
        src.fail(field, medium.density.source + ": optical depth " + num(tau) +
                            " across one voxel (largest extinction x scale x largest voxel value x voxel size) is beyond " +
                            num(kMaxVoxelOpticalDepth) + "; lower the scale or the coefficients");
}

// "density": {"uri": "smoke.vdb", "grid": "density", "scale": 1}: the coefficients become per
// unit density; the grid sits in world space until a mesh's node places it (placeInteriorGrid).
// Both check the medium's density against the limit (checkOpticalDepth).
void parseDensity(const Source& src, const tinygltf::Value& d, const std::string& field, Medium& medium,
                  std::vector<std::string>& files) {
    if (!d.IsObject()) src.fail(field, "expected an object {\"uri\": ..., \"grid\": ..., \"scale\": ...}");
    const tinygltf::Value* uri = member(d, "uri");
    if (!uri || !uri->IsString() || uri->Get<std::string>().empty())
        src.fail(field + ".uri", "expected the path of an OpenVDB file, relative to the scene file");
    std::string gridName;
    if (const tinygltf::Value* g = member(d, "grid")) {
        if (!g->IsString()) src.fail(field + ".grid", "expected a string");
        gridName = g->Get<std::string>();
    }
    double scale = 1;
    if (const tinygltf::Value* s = member(d, "scale")) {
        if (!s->IsNumber()) src.fail(field + ".scale", "expected a number");
        scale = s->GetNumberAsDouble();
        if (!std::isfinite(scale) || scale < 0 || scale > 1e30) src.fail(field + ".scale", "scale " + num(scale) + " must be finite and >= 0");
    }
    const std::string path = besideScene(src, uri->Get<std::string>());
    VdbDensity vdb;
    if (!std::ifstream(path)) src.fail(field + ".uri", "cannot open '" + path + "': " + std::strerror(errno));
    try {
        vdb = loadVdbDensity(path, gridName);
    } catch (const SceneError& e) {
        src.fail(field + ".uri", e.what());  // "<vdb path>: <problem>", after the scene's path and field
    }
    if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
    medium.density.grid = vdb.grid;
    medium.density.indexToWorld = vdb.indexToWorld;
    medium.density.scale = float(scale);
    medium.density.source = path + ": grid \"" + (gridName.empty() ? vdb.gridName : gridName) + "\"";
    medium.density.place(Mat4());
    checkOpticalDepth(src, medium, Mat4(), field);
}

Medium parseMedium(const Source& src, const tinygltf::Value& m, const std::string& field, std::vector<std::string>& files) {
    if (!m.IsObject()) src.fail(field, "expected an object");
    Medium medium;
    if (const tinygltf::Value* name = member(m, "name")) {
        if (!name->IsString()) src.fail(field + ".name", "expected a string");
        medium.name = name->Get<std::string>();
    }
    medium.sigmaS = coefficient(src, member(m, "scattering"), field + ".scattering");
    medium.sigmaA = coefficient(src, member(m, "absorption"), field + ".absorption");
    if (const tinygltf::Value* g = member(m, "anisotropy")) {
        if (!g->IsNumber()) src.fail(field + ".anisotropy", "expected a number");
        double d = g->GetNumberAsDouble();
        if (!std::isfinite(d)) src.fail(field + ".anisotropy", "non-finite anisotropy " + num(d));
        if (std::abs(d) >= 1) src.fail(field + ".anisotropy", "anisotropy g = " + num(d) + " must satisfy |g| < 1");
        medium.g = float(d);
    }
    if (const tinygltf::Value* d = member(m, "density")) parseDensity(src, *d, field + ".density", medium, files);
    return medium;
}

}  // namespace

void parseMedia(const Source& src, const tinygltf::Value& brumeMedia, SceneDescription& desc) {
    const std::string base = "extensions.BRUME_media";
    if (!brumeMedia.IsObject()) src.fail(base, "expected an object");
    if (const tinygltf::Value* media = member(brumeMedia, "media")) {
        if (!media->IsArray()) src.fail(base + ".media", "expected an array");
        for (size_t i = 0; i < media->ArrayLen(); ++i)
            desc.media.push_back(parseMedium(src, media->Get(int(i)), at(base + ".media", i), desc.files));
    }
    desc.ambientMedium = -1;
    if (const tinygltf::Value* ambient = member(brumeMedia, "ambient")) {
        const std::string field = base + ".ambient";
        desc.ambientMedium = checkIndex(src, integer(src, *ambient, field), desc.media.size(), field, "medium");
    }
}

void placeInteriorGrid(const Source& src, Medium& medium, int mediumIndex, const Mat4& world, const std::string& field) {
    if (!medium.heterogeneous()) return;
    if (medium.density.placedByNode) {
        GridPlacement probe = medium.density;
        probe.place(world);
        for (int i = 0; i < 16; ++i)
            if (std::abs(probe.worldToLocal.m[size_t(i)] - medium.density.worldToLocal.m[size_t(i)]) > 1e-9)
                src.fail(field, "medium " + std::to_string(mediumIndex) +
                                    " has a density grid and bounds meshes of nodes with different transforms: "
                                    "give each its own medium");
        return;
    }
    medium.density.place(world);
    medium.density.placedByNode = true;
    checkOpticalDepth(src, medium, world, field);
}

int interiorMedium(const Source& src, const tinygltf::Mesh& mesh, int meshIndex, int mediaCount) {
    auto it = mesh.extensions.find("BRUME_media");
    if (it == mesh.extensions.end()) return -1;
    const std::string field = at("meshes", size_t(meshIndex)) + ".extensions.BRUME_media";
    if (!it->second.IsObject()) src.fail(field, "expected an object");
    const tinygltf::Value* interior = member(it->second, "interior");
    if (!interior) return -1;
    return checkIndex(src, integer(src, *interior, field + ".interior"), size_t(mediaCount), field + ".interior",
                      "medium");
}

}  // namespace brume::gltf
