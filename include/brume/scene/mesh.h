// One glTF triangle primitive, flattened into world space.
#pragma once
#include <cstdint>
#include <vector>
#include "brume/math/vec3.h"

namespace brume {

struct Mesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;    // per vertex, world space; empty = use geometric normal
    std::vector<float> uvs;       // 2 per vertex; empty = no texture coordinates
    std::vector<uint32_t> indices;  // 3 per triangle, counter-clockwise = front face
    int material = -1;            // index into materials
    int interiorMedium = -1;      // BRUME_media "interior": the medium this closed mesh encloses
    int triangleCount() const { return int(indices.size() / 3); }
};

}  // namespace brume
