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

// Render settings a scene file may suggest (the root extension BRUME_render, written by the
// Blender exporter): the command line's defaults when its own options are not given. 0 (and
// maxDepth -2) = not given.
struct RenderSettings {
    int width = 0, height = 0;  // both or neither
    int spp = 0;
    int maxDepth = -2;          // -1: unlimited
};

struct SceneDescription {
    std::string path;               // the file it came from, for messages
    Camera camera;
    std::vector<Mesh> meshes;
    std::vector<Material> materials;  // meshes without a glTF material get their own entry
    std::vector<Texture> textures;
    std::vector<Medium> media;
    int ambientMedium = -1;           // fills space outside bounded media; -1 = vacuum
    std::vector<Light> lights;        // punctual lights only; emissive triangles are added by Scene
    RenderSettings render;            // from BRUME_render, if the file has it
    // Every file the scene was read from, each once, as opened: the scene file first, then
    // the buffers and images it names by URI and its density grids. A scene's identity
    // (checkpoints, MPI ranks, bench references) is their contents.
    std::vector<std::string> files;
    // What the loader noticed and went on past, one line each ("<path>: <field>: ..."):
    // unknown fields of the brume extensions. The command prints them.
    std::vector<std::string> warnings;
};

}  // namespace brume
