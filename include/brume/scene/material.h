// A glTF metallic-roughness material reduced to what brume renders.
#pragma once
#include "brume/math/vec3.h"

namespace brume {

enum class MaterialKind {
    Diffuse,     // metallic == 0: Lambertian baseColor
    Glossy,      // metallic > 0: (1−metallic)·Lambert + metallic·GGX conductor, F0 = baseColor
    Dielectric,  // KHR_materials_transmission = 1: smooth glass with KHR_materials_ior
    Invisible,   // a medium boundary with no material, or a transparent emitter: rays pass straight on
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
    // A light surface as Cycles' lights are (extras "transparent"): kind Invisible, so every
    // ray crosses it (none is shadowed, nothing reflects), and it still emits; a walk that
    // crosses it gathers that emission (path_tracer.cpp, bdpt_crossings.h).
    bool transparent = false;
    // Seen by camera rays (extras "cameraVisible", only with "transparent"): Cycles 3.4 leaves
    // area lights out of camera rays. Light reaching the pinhole straight from such a surface
    // counts nothing, by any strategy; after a bounce it counts.
    bool cameraVisible = true;
    bool isEmissive() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
};

}  // namespace brume
