// The brume sub-commands. Each takes the arguments after its name (parsed by CLI11, see
// command_line.h) and returns the exit code; problems are thrown (UsageError → 2, SceneError
// and other run-time errors → 1) and reported by main().
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "brume/cli/value_parsers.h"
#include "brume/scene/scene.h"

namespace brume::cli {

int runRender(const std::vector<std::string>& args);
int runRaybench(const std::vector<std::string>& args);
int runBench(const std::vector<std::string>& args);

// Shared by the commands (scene_setup.cpp): loads a glTF file (SceneError on failure) and
// prints its warnings on stderr (not on MPI ranks other than 0: printWarnings false).
SceneDescription loadSceneDescription(const std::string& path, bool printWarnings = true);
// The image size: `requested` if set (width > 0), else 640 wide with the camera's aspect
// ratio (640x480 when the camera has none). Throws std::runtime_error if the camera's
// aspect ratio asks for an image beyond the limits.
Resolution imageResolution(const Camera& camera, Resolution requested);

}  // namespace brume::cli
