// glTF loader: triangle primitives flattened into world-space brume meshes.
#include <utility>

#include "brume/scene/gltf_detail.h"

namespace brume::gltf {

namespace {

int fallbackMaterial(SceneDescription& desc, FallbackMaterials& fallback, bool invisible) {
    int& slot = invisible ? fallback.invisible : fallback.diffuse;
    if (slot < 0) {
        Material m;
        m.kind = invisible ? MaterialKind::Invisible : MaterialKind::Diffuse;
        m.baseColor = Spectrum(0.8f);
        slot = int(desc.materials.size());
        desc.materials.push_back(m);
    }
    return slot;
}

}  // namespace

void appendMesh(const Source& src, const tinygltf::Model& model, int meshIndex, const Mat4& world,
                const std::string& field, SceneDescription& desc, FallbackMaterials& fallback) {
    checkIndex(src, meshIndex, model.meshes.size(), field, "mesh");
    const tinygltf::Mesh& gm = model.meshes[size_t(meshIndex)];
    const std::string meshField = at("meshes", size_t(meshIndex));
    const int interior = interiorMedium(src, gm, meshIndex, int(desc.media.size()));
    if (interior >= 0) placeInteriorGrid(src, desc.media[size_t(interior)], interior, world, field);
    // A mirroring transform turns counter-clockwise triangles clockwise: swap two corners back.
    const bool mirrored = world.det3() < 0;

    for (size_t p = 0; p < gm.primitives.size(); ++p) {
        const tinygltf::Primitive& prim = gm.primitives[p];
        if (prim.mode != TINYGLTF_MODE_TRIANGLES) continue;  // points, lines, strips, fans
        const std::string pf = at(meshField + ".primitives", p);
        Mesh mesh;

        auto attribute = [&](const char* name) {
            auto it = prim.attributes.find(name);
            return it == prim.attributes.end() ? -1 : it->second;
        };
        const int positionAccessor = attribute("POSITION");
        if (positionAccessor < 0) src.fail(pf + ".attributes", "no POSITION attribute");
        std::vector<float> P =
            readFloats(src, model, positionAccessor, pf + ".attributes.POSITION", TINYGLTF_TYPE_VEC3, false);
        const size_t n = P.size() / 3;
        mesh.positions.reserve(n);
        for (size_t i = 0; i < n; ++i) {
            Vec3 w = world.point(Vec3(P[3 * i], P[3 * i + 1], P[3 * i + 2]));
            if (!isFinite(w)) src.fail(field, "the node transform takes vertex " + std::to_string(i) + " of " + pf +
                                                  " to infinity");
            mesh.positions.push_back(w);
        }

        if (int a = attribute("NORMAL"); a >= 0) {
            std::vector<float> N = readFloats(src, model, a, pf + ".attributes.NORMAL", TINYGLTF_TYPE_VEC3, false);
            if (N.size() != P.size())
                src.fail(pf + ".attributes.NORMAL", std::to_string(N.size() / 3) + " normals for " +
                                                        std::to_string(n) + " positions");
            mesh.normals.reserve(n);
            for (size_t i = 0; i < n; ++i)
                mesh.normals.push_back(world.normal(Vec3(N[3 * i], N[3 * i + 1], N[3 * i + 2])));
        }

        if (int a = attribute("TEXCOORD_0"); a >= 0) {
            mesh.uvs = readFloats(src, model, a, pf + ".attributes.TEXCOORD_0", TINYGLTF_TYPE_VEC2, true);
            if (mesh.uvs.size() != 2 * n)
                src.fail(pf + ".attributes.TEXCOORD_0", std::to_string(mesh.uvs.size() / 2) +
                                                            " texture coordinates for " + std::to_string(n) +
                                                            " positions");
        }

        if (prim.indices != -1) {
            mesh.indices = readIndices(src, model, prim.indices, pf + ".indices");
            for (size_t i = 0; i < mesh.indices.size(); ++i)
                if (mesh.indices[i] >= n)
                    src.fail(pf + ".indices", "element " + std::to_string(i) + " of " +
                                                  at("accessors", size_t(prim.indices)) + " is " +
                                                  std::to_string(mesh.indices[i]) + ", but there are only " +
                                                  std::to_string(n) + " vertices");
            if (mesh.indices.size() % 3 != 0)
                src.fail(pf + ".indices", std::to_string(mesh.indices.size()) +
                                              " indices do not make whole triangles");
        } else {
            if (n % 3 != 0)
                src.fail(pf + ".attributes.POSITION", std::to_string(n) +
                                                          " vertices without indices do not make whole triangles");
            mesh.indices.resize(n);
            for (size_t i = 0; i < n; ++i) mesh.indices[i] = uint32_t(i);
        }
        if (mesh.indices.empty()) continue;  // nothing to render
        if (mirrored)
            for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);

        if (prim.material != -1)
            mesh.material = checkIndex(src, prim.material, model.materials.size(), pf + ".material", "material");
        else
            mesh.material = fallbackMaterial(desc, fallback, interior >= 0);
        mesh.interiorMedium = interior;
        desc.meshes.push_back(std::move(mesh));
    }
}

}  // namespace brume::gltf
