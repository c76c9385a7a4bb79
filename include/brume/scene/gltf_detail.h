// Internals of the glTF loader (src/scene/gltf_*.cpp), declared here so the parts can be
// tested on their own. Users want brume/scene/gltf_loader.h instead.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "brume/math/mat4.h"
#include "brume/scene/gltf_loader.h"

namespace brume::gltf {

// --- Messages (gltf_file.cpp) -------------------------------------------------------------

// The file being loaded: every error names it.
struct Source {
    std::string path;
    // Throws SceneError("<path>: <field>: <problem>"), flattened to one line.
    [[noreturn]] void fail(const std::string& field, const std::string& problem) const;
};

std::string num(double v);                             // a number as a message shows it
std::string at(const std::string& field, size_t i);    // "field[i]"
// Returns index if 0 <= index < count, else fails: "<noun> <index> out of range (<count> in file)".
int checkIndex(const Source& src, int index, size_t count, const std::string& field, const char* noun);

// Reads and parses the file (by extension: .gltf or .glb) and checks that every buffer and
// every image referenced by URI could be read. Images stored in buffer views are not decoded
// yet (see decodeImage), so that their bounds can be checked first.
tinygltf::Model readModel(const Source& src);

// The paths of the files a model's buffers and images name by URI (not data: URIs), resolved
// against the scene file's directory as tinygltf resolved them, appended to `files` unless
// already there.
void addReferencedFiles(const Source& src, const tinygltf::Model& model, std::vector<std::string>& files);
// A path relative to the scene file's directory (absolute paths as they are).
std::string besideScene(const Source& src, const std::string& relative);

// --- JSON values of extensions and extras (gltf_file.cpp) ---------------------------------

// object[key], or nullptr if object is not an object or has no such key.
const tinygltf::Value* member(const tinygltf::Value& object, const char* key);
double finiteNumber(const Source& src, const tinygltf::Value& v, const std::string& field);
int integer(const Source& src, const tinygltf::Value& v, const std::string& field);

// --- Accessors (gltf_accessor.cpp) --------------------------------------------------------

// Reads accessor `index` (used as `usage`, e.g. "meshes[0].primitives[0].attributes.NORMAL")
// as floats, components per element. It must have the given TINYGLTF_TYPE_*; FLOAT
// components, or normalized unsigned bytes/shorts when allowNormalized. Every value must be
// finite. Bounds of accessor, buffer view and buffer are checked.
std::vector<float> readFloats(const Source& src, const tinygltf::Model& model, int index, const std::string& usage,
                              int type, bool allowNormalized);
// Reads a SCALAR accessor of unsigned bytes, shorts or ints.
std::vector<uint32_t> readIndices(const Source& src, const tinygltf::Model& model, int index,
                                  const std::string& usage);
// The bytes of buffer view `index` (referenced from `field`), checked against its buffer.
const unsigned char* bufferViewBytes(const Source& src, const tinygltf::Model& model, int index,
                                     const std::string& field, size_t* length);

// --- Meshes (gltf_mesh.cpp) ---------------------------------------------------------------

// Materials for primitives without one, appended to SceneDescription::materials on first use.
struct FallbackMaterials {
    int diffuse = -1;    // Diffuse, baseColor 0.8
    int invisible = -1;  // Invisible: boundary of a medium
};

// Appends one brume Mesh per triangle primitive of model.meshes[meshIndex], placed by world.
// field names the reference, e.g. "nodes[3].mesh".
void appendMesh(const Source& src, const tinygltf::Model& model, int meshIndex, const Mat4& world,
                const std::string& field, SceneDescription& desc, FallbackMaterials& fallback);

// --- Materials and textures (gltf_material.cpp) -------------------------------------------

// Converts model.materials into desc.materials (same indices) and the textures they use
// into desc.textures.
void loadMaterials(const Source& src, const tinygltf::Model& model, SceneDescription& desc);
// The exact sRGB EOTF, encoded value in [0, 1] to linear.
double srgbToLinear(double encoded);
// Decodes image 8 or 16 bits, 1–4 channels (grey, grey+alpha, RGB, RGBA; alpha dropped)
// from sRGB into linear RGB. field names the image in messages.
Texture decodeSrgbImage(const Source& src, const tinygltf::Image& image, const std::string& field);

// --- Media (gltf_media.cpp) ---------------------------------------------------------------

// Parses the root BRUME_media extension object into desc.media and desc.ambientMedium.
void parseMedia(const Source& src, const tinygltf::Value& brumeMedia, SceneDescription& desc);
// The medium a mesh's BRUME_media extension names as its interior, or -1.
int interiorMedium(const Source& src, const tinygltf::Mesh& mesh, int meshIndex, int mediaCount);
// A medium with a density grid inside a mesh: the mesh's node transform places the grid.
void placeInteriorGrid(const Source& src, Medium& medium, int mediumIndex, const Mat4& world, const std::string& field);

// --- Lights (gltf_light.cpp) --------------------------------------------------------------

// A KHR_lights_punctual light placed by a node's world transform. field names the reference.
Light makeLight(const Source& src, const tinygltf::Model& model, int lightIndex, const Mat4& world,
                const std::string& field);

}  // namespace brume::gltf
