// Reading a density grid from an OpenVDB file (docs/scene-format.md, "density grids").
#pragma once
#include <memory>
#include <string>
#include "brume/math/mat4.h"
#include "brume/scene/density_grid.h"

namespace brume {

struct VdbDensity {
    std::shared_ptr<const DensityGrid> grid;
    Mat4 indexToWorld;  // the grid's own (affine) transform: index space → its world
    std::string gridName;  // the grid read (the first float grid when none was named)
};

// Loads float grid `gridName` (empty: the first float grid) of `path`. Throws SceneError
// "<path>: <problem>" for a missing or unreadable file, a missing grid, a grid that is not
// float, a non-affine transform, or a negative or non-finite voxel value.
VdbDensity loadVdbDensity(const std::string& path, const std::string& gridName);

}  // namespace brume
