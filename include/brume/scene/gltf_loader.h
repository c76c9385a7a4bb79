// Loads a glTF 2.0 scene (.gltf with embedded or external buffers, or .glb) into a
// SceneDescription. The scene format, with brume's conventions and the BRUME_media extension,
// is described in docs/scene-format.md.
#pragma once
#include <stdexcept>
#include <string>
#include "brume/scene/scene_description.h"

namespace brume {

// A scene file that cannot be loaded. what() is one line: "<path>: <field>: <problem>", where
// <field> is a JSON path into the file such as "meshes[0].primitives[1].attributes.POSITION"
// or "extensions.BRUME_media.media[0].scattering" ("file", "JSON", "GLB" for problems with
// the file as a whole).
struct SceneError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Throws SceneError for anything the renderer cannot use: see docs/scene-format.md.
SceneDescription loadGltf(const std::string& path);

}  // namespace brume
