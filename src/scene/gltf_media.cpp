// glTF loader: the BRUME_media extension (homogeneous media, the ambient medium, and the
// medium a closed mesh encloses).
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <limits>

#include "brume/math/blackbody.h"
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

// A warning for every member of `object` that is not among `known` (a misspelt field would
// otherwise be ignored without a word).
void warnUnknown(const Source& src, const tinygltf::Value& object, std::initializer_list<const char*> known,
                 const std::string& field, std::vector<std::string>& warnings) {
    if (!object.IsObject()) return;
    for (const std::string& key : object.Keys()) {
        bool found = false;
        for (const char* k : known) found |= key == k;
        if (!found) warnings.push_back(src.path + ": " + field + ": unknown field \"" + key + "\" (ignored)");
    }
}

// A grid reference {"uri": "smoke.vdb", "grid": "density", "scale": 1}, loaded (or shared with
// `same`, a grid the medium already has from the same file and name) and sitting in world
// space until a mesh's node places it (placeInteriorGrid).
GridPlacement loadGrid(const Source& src, const tinygltf::Value& d, const std::string& field, const GridPlacement* same,
                       std::vector<std::string>& files) {
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
    GridPlacement placement;
    placement.requested = path + "\n" + gridName;
    if (same && same->grid && same->requested == placement.requested) {
        placement = *same;
        placement.scale = float(scale);
        return placement;
    }
    VdbDensity vdb;
    if (!std::ifstream(path)) src.fail(field + ".uri", "cannot open '" + path + "': " + std::strerror(errno));
    try {
        vdb = loadVdbDensity(path, gridName);
    } catch (const SceneError& e) {
        src.fail(field + ".uri", e.what());  // "<vdb path>: <problem>", after the scene's path and field
    }
    if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
    placement.grid = vdb.grid;
    placement.indexToWorld = vdb.indexToWorld;
    placement.scale = float(scale);
    placement.source = path + ": grid \"" + (gridName.empty() ? vdb.gridName : gridName) + "\"";
    placement.place(Mat4());
    return placement;
}

// "density": {"uri": ..., "grid": ..., "scale": ...}: the coefficients become per unit
// density; checked against the limit (checkOpticalDepth).
void parseDensity(const Source& src, const tinygltf::Value& d, const std::string& field, Medium& medium,
                  std::vector<std::string>& files, std::vector<std::string>& warnings) {
    if (!d.IsObject()) src.fail(field, "expected an object {\"uri\": ..., \"grid\": ..., \"scale\": ...}");
    warnUnknown(src, d, {"uri", "grid", "scale"}, field, warnings);
    medium.density = loadGrid(src, d, field, nullptr, files);
    checkOpticalDepth(src, medium, Mat4(), field);
}

// "emission": [r, g, b] (or a number): radiance per metre, the same everywhere in the medium;
// or {"rgb": [r, g, b], "uri": ..., "grid": ..., "scale": s}: rgb × s × the grid's value,
// placed as the density grid is (it may be the density grid itself: then shared).
void parseEmission(const Source& src, const tinygltf::Value& e, const std::string& field, Medium& medium,
                   std::vector<std::string>& files, std::vector<std::string>& warnings) {
    if (!e.IsObject()) {
        medium.emission = coefficient(src, &e, field);
        return;
    }
    warnUnknown(src, e, {"rgb", "uri", "grid", "scale"}, field, warnings);
    const tinygltf::Value* rgb = member(e, "rgb");
    medium.emission = rgb ? coefficient(src, rgb, field + ".rgb") : Spectrum(1.0f);
    medium.emissionGrid = loadGrid(src, e, field, &medium.density, files);
}

double boundedNumber(const Source& src, const tinygltf::Value& v, const std::string& field, double lo, double hi) {
    if (!v.IsNumber()) src.fail(field, "expected a number");
    const double d = v.GetNumberAsDouble();
    if (!(d >= lo && d <= hi)) src.fail(field, num(d) + " is outside [" + num(lo) + ", " + num(hi) + "]");
    return d;
}

// "blackbody": Cycles' Principled Volume blackbody (math/blackbody.h): {"temperature": K} for one
// temperature, or {"uri", "grid", "scale"} for a temperature grid (kelvin = scale × the grid's
// value, placed like "density", which it may be); with "intensity" b in [0, 1] (default 1) and
// "tint" [r, g, b] (default 1). A constant temperature adds to "emission"; a grid cannot be
// combined with "emission" (a medium has one emission grid).
void parseBlackbody(const Source& src, const tinygltf::Value& b, const std::string& field, Medium& medium,
                    std::vector<std::string>& files, std::vector<std::string>& warnings) {
    if (!b.IsObject())
        src.fail(field, "expected an object {\"temperature\": kelvin} or {\"uri\": ..., \"grid\": ..., \"scale\": ...}");
    warnUnknown(src, b, {"temperature", "uri", "grid", "scale", "intensity", "tint"}, field, warnings);
    const tinygltf::Value* t = member(b, "temperature");
    const bool grid = member(b, "uri") != nullptr;
    if (t && grid) src.fail(field, "give either \"temperature\" or a grid (\"uri\"), not both");
    if (!t && !grid) src.fail(field, "expected \"temperature\" (kelvin) or a temperature grid (\"uri\")");
    float intensity = 1;
    if (const tinygltf::Value* i = member(b, "intensity")) intensity = float(boundedNumber(src, *i, field + ".intensity", 0, 1));
    const tinygltf::Value* tintValue = member(b, "tint");
    const Spectrum tint = tintValue ? coefficient(src, tintValue, field + ".tint") : Spectrum(1.0f);
    if (t) {
        const float kelvin = float(boundedNumber(src, *t, field + ".temperature", 0, 1e6));
        if (medium.emissionGrid.grid)
            src.fail(field, "a blackbody of one temperature cannot be added to an emission grid; give it in the grid's \"rgb\"");
        medium.emission += tint * blackbodyEmission(kelvin, intensity);
        return;
    }
    if (medium.emissive() || medium.emissionGrid.grid)
        src.fail(field, "a blackbody temperature grid cannot be combined with \"emission\" in one medium");
    medium.emission = tint;
    medium.emissionGrid = loadGrid(src, b, field, &medium.density, files);
    medium.blackbody = true;
    medium.blackbodyIntensity = intensity;
}

Medium parseMedium(const Source& src, const tinygltf::Value& m, const std::string& field, std::vector<std::string>& files,
                   std::vector<std::string>& warnings) {
    if (!m.IsObject()) src.fail(field, "expected an object");
    warnUnknown(src, m, {"name", "scattering", "absorption", "anisotropy", "density", "emission", "blackbody"}, field,
                warnings);
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
    if (const tinygltf::Value* d = member(m, "density")) parseDensity(src, *d, field + ".density", medium, files, warnings);
    if (const tinygltf::Value* e = member(m, "emission")) parseEmission(src, *e, field + ".emission", medium, files, warnings);
    if (const tinygltf::Value* b = member(m, "blackbody")) parseBlackbody(src, *b, field + ".blackbody", medium, files, warnings);
    return medium;
}

// The ambient medium fills all space, so a ray may cross it to infinity: its emission must
// fade there. Refused: constant emission in a channel without extinction (the radiance would be
// infinite), and constant emission in a grid medium (emitting out past the grid, where nothing
// absorbs).
void checkAmbientEmission(const Source& src, const Medium& medium, const std::string& field) {
    if (!medium.emissive() || medium.emissionGrid.grid) return;
    if (medium.heterogeneous())
        src.fail(field + ".emission", "the ambient medium has a density grid and emission without a grid: it would "
                                      "emit out to infinity; give the emission a grid, or put the medium inside a mesh");
    const Spectrum st = medium.sigmaT();
    for (int c = 0; c < 3; ++c)
        if (medium.emission[c] != 0 && !(st[c] > 0))
            src.fail(field + ".emission", "the ambient medium emits in a channel where it has no extinction: the "
                                          "radiance would be infinite; give it absorption or scattering there");
}

}  // namespace

void parseMedia(const Source& src, const tinygltf::Value& brumeMedia, SceneDescription& desc) {
    const std::string base = "extensions.BRUME_media";
    if (!brumeMedia.IsObject()) src.fail(base, "expected an object");
    warnUnknown(src, brumeMedia, {"media", "ambient"}, base, desc.warnings);
    if (const tinygltf::Value* media = member(brumeMedia, "media")) {
        if (!media->IsArray()) src.fail(base + ".media", "expected an array");
        for (size_t i = 0; i < media->ArrayLen(); ++i)
            desc.media.push_back(parseMedium(src, media->Get(int(i)), at(base + ".media", i), desc.files, desc.warnings));
    }
    desc.ambientMedium = -1;
    if (const tinygltf::Value* ambient = member(brumeMedia, "ambient")) {
        const std::string field = base + ".ambient";
        desc.ambientMedium = checkIndex(src, integer(src, *ambient, field), desc.media.size(), field, "medium");
        checkAmbientEmission(src, desc.media[size_t(desc.ambientMedium)], at(base + ".media", size_t(desc.ambientMedium)));
    }
}

void placeInteriorGrid(const Source& src, Medium& medium, int mediumIndex, const Mat4& world, const std::string& field) {
    if (!medium.heterogeneous() && !medium.emissionGrid.grid) return;
    const GridPlacement& lead = medium.heterogeneous() ? medium.density : medium.emissionGrid;
    if (lead.placedByNode) {
        GridPlacement probe = lead;
        probe.place(world);
        for (int i = 0; i < 16; ++i)
            if (std::abs(probe.worldToLocal.m[size_t(i)] - lead.worldToLocal.m[size_t(i)]) > 1e-9)
                src.fail(field, "medium " + std::to_string(mediumIndex) +
                                    " has a grid and bounds meshes of nodes with different transforms: "
                                    "give each its own medium");
        return;
    }
    for (GridPlacement* g : {&medium.density, &medium.emissionGrid})
        if (g->grid) {
            g->place(world);
            g->placedByNode = true;
        }
    if (medium.heterogeneous()) checkOpticalDepth(src, medium, world, field);
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
