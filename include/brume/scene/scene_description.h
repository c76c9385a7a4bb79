// What a scene file says, as plain data: the loader fills it, Scene builds on it.
#pragma once
#include <string>
#include <vector>
#include "brume/scene/camera.h"
#include "brume/scene/light.h"
#include "brume/scene/material.h"
#include "brume/scene/medium.h"
#include "brume/scene/mesh.h"
#include "brume/scene/texture.h"

namespace brume {

struct SceneDescription {
    std::string path;               // the file it came from, for messages
    Camera camera;
    std::vector<Mesh> meshes;
    std::vector<Material> materials;  // meshes without a glTF material get their own entry
    std::vector<Texture> textures;
    std::vector<Medium> media;
    int ambientMedium = -1;           // fills space outside bounded media; -1 = vacuum
    std::vector<Light> lights;        // punctual lights only; emissive triangles are added by Scene
};

}  // namespace brume
