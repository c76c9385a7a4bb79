// A scene's identity: the contents of every file it was read from (SceneDescription::files:
// the .gltf, its .bin buffers and images, its .vdb grids). Editing any of them changes the
// scene, so a checkpoint refuses to resume it, MPI ranks refuse to render it together, and a
// bench reference is rendered again.
#pragma once
#include <cstdint>

#include "brume/render/checkpoint.h"
#include "brume/scene/scene_description.h"

namespace brume {

// One checkpoint setting per file, the file's FNV-1a hash: first "the scene file's FNV-1a
// hash", then "the FNV-1a hash of <path>" with the path relative to the scene file's
// directory, so that a mismatch names the file that changed. (A scene read from one file has
// the one setting checkpoints always had.) Throws std::runtime_error if a file cannot be read.
CheckpointSettings sceneFileSettings(const SceneDescription& desc);

// One hash of all of them: the scene file's own hash when it is the only file.
uint64_t sceneContentHash(const SceneDescription& desc);

}  // namespace brume
