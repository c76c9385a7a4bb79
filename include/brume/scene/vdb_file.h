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
    std::string gridName;  // the grid read (the first float or double grid when none was named)
};

// Loads grid `gridName` (empty: the first float or double grid) of `path`: a float grid (also
// one saved as half floats) or a double grid (rounded to float), into sparse bricks. Throws
// SceneError "<path>: <problem>" for a missing or unreadable file, a missing grid, a grid of
// other values (vectors), a non-affine transform, a box beyond the brick tables, or a
// negative or non-finite voxel value.
VdbDensity loadVdbDensity(const std::string& path, const std::string& gridName);

}  // namespace brume
