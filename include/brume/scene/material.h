// A glTF metallic-roughness material reduced to what brume renders.
#pragma once
#include "brume/math/vec3.h"

namespace brume {

enum class MaterialKind {
    Diffuse,     // metallic == 0: Lambertian baseColor
    Glossy,      // metallic > 0: (1−metallic)·Lambert + metallic·GGX conductor, F0 = baseColor
    Dielectric,  // KHR_materials_transmission = 1: smooth glass with KHR_materials_ior
    Invisible,   // a medium boundary with no material: index-matched, rays pass straight on
};

struct Material {
    MaterialKind kind = MaterialKind::Diffuse;
    Spectrum baseColor{0.8f};
    int baseColorTexture = -1;  // index into SceneDescription::textures, -1 none
    float metallic = 0;
    float roughness = 1;
    float ior = 1.5f;
    Spectrum emission{0.0f};    // emissiveFactor × emissiveStrength [W/(m² sr)]
    int emissiveTexture = -1;   // multiplies emission
    bool doubleSided = false;   // emits from both faces
    bool isEmissive() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
};

}  // namespace brume
