// OpenVDB → DensityGrid: the bricks the active voxels and tiles reach, copied into sparse
// bricks (inactive voxels and everything outside are 0), and the grid's affine index → world map.
#include "brume/scene/vdb_file.h"

#include <cmath>
#include <mutex>

#include <openvdb/openvdb.h>

#include "brume/scene/gltf_loader.h"

namespace brume {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) { throw SceneError(path + ": " + problem); }

// The brick tables are dense over the box, 12 bytes a brick of 512 voxels: refuse boxes whose
// tables would pass 3 GiB (2^28 bricks; Disney's cloud, 6.6e9 voxels, needs 150 MiB).
constexpr double kMaxBoxVoxels = double(uint64_t(1) << 37);

// The sparse bricks of a float or double grid (double values rounded to float). Throws
// SceneError for a box beyond the brick tables and for a negative or non-finite value.
template <class GridT>
std::shared_ptr<DensityGrid> bricksOf(const GridT& grid, const std::string& path, const std::string& name) {
    auto dg = std::make_shared<DensityGrid>();
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    int lo[3] = {0, 0, 0}, hi[3] = {-1, -1, -1};  // (no active voxel: an all-zero grid)
    if (!box.empty()) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = box.min()[a];
            hi[a] = box.max()[a];
        }
        const double voxels = double(hi[0] - lo[0] + 3) * (hi[1] - lo[1] + 3) * (hi[2] - lo[2] + 3);
        if (voxels > kMaxBoxVoxels)
            fail(path, "grid \"" + name + "\" spans " + std::to_string(int64_t(voxels)) +
                           " voxels, more than the brick tables cover (2^37)");
    }
    dg->layout(lo, hi);

    // The bricks the active values reach: a brick keeps local voxels [8c, 8c + 8] per axis, so
    // an active index box [a, b] reaches bricks c with 8c ≤ b − origin and 8c + 8 ≥ a − origin.
    // Leaves and active tiles are marked by their whole boxes; a marked brick all of whose
    // voxels turn out 0 is not stored (storeBrick).
    const int B = DensityGrid::kBrick;
    std::vector<uint8_t> reached(dg->brick.size(), 0);
    auto mark = [&](const openvdb::Coord& a, const openvdb::Coord& b) {
        int c0[3], c1[3];
        for (int ax = 0; ax < 3; ++ax) {
            const int x0 = std::max(a[ax], lo[ax]) - dg->origin[ax], x1 = std::min(b[ax], hi[ax]) - dg->origin[ax];
            if (x1 < x0) return;
            c0[ax] = std::max(0, (x0 - 1) / B);  // (x0 ≥ 1: origin < lo)
            c1[ax] = std::min(dg->bn[ax] - 1, x1 / B);
        }
        for (int z = c0[2]; z <= c1[2]; ++z)
            for (int y = c0[1]; y <= c1[1]; ++y)
                for (int x = c0[0]; x <= c1[0]; ++x) reached[(size_t(z) * dg->bn[1] + y) * dg->bn[0] + x] = 1;
    };
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf)
        if (!leaf->isEmpty()) mark(leaf->origin(), leaf->origin() + openvdb::Coord(B - 1));
    {
        typename GridT::TreeType::ValueOnCIter tile = grid.tree().cbeginValueOn();
        tile.setMaxDepth(tile.getLeafDepth() - 1);  // tiles above the leaves only
        for (; tile; ++tile) {
            openvdb::CoordBBox tb;
            tile.getBoundingBox(tb);
            mark(tb.min(), tb.max());
        }
    }
    size_t count = 0;
    for (uint8_t r : reached) count += r;
    dg->voxels.reserve(count * size_t(DensityGrid::kBrickVoxels));
    auto acc = grid.getConstAccessor();
    std::string bad;
    auto value = [&](int i, int j, int k) -> float {
        const openvdb::Coord c(i, j, k);
        if (!acc.isValueOn(c)) return 0.0f;
        const float v = float(acc.getValue(c));  // (a double beyond float's range: infinite)
        if (!(v >= 0) || !std::isfinite(v)) {
            if (bad.empty())
                bad = "grid \"" + name + "\" has " + (std::isnan(v) ? "a NaN" : std::isinf(v) ? "an infinite" : "a negative") +
                      " voxel value " + std::to_string(v) + " at (" + std::to_string(i) + ", " + std::to_string(j) + ", " +
                      std::to_string(k) + ")";
            return 0.0f;
        }
        return v;
    };
    for (int z = 0; z < dg->bn[2]; ++z)
        for (int y = 0; y < dg->bn[1]; ++y)
            for (int x = 0; x < dg->bn[0]; ++x)
                if (reached[(size_t(z) * dg->bn[1] + y) * dg->bn[0] + x]) dg->storeBrick(x, y, z, value);
    if (!bad.empty()) fail(path, bad);
    return dg;
}

}  // namespace

VdbDensity loadVdbDensity(const std::string& path, const std::string& gridName) {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
    openvdb::GridBase::Ptr base;
    std::string name = gridName;
    try {
        openvdb::io::File file(path);
        file.open(false);
        if (name.empty()) {
            // The first float or double grid, by reading each grid's metadata only.
            openvdb::GridPtrVecPtr metas = file.readAllGridMetadata();
            for (const openvdb::GridBase::Ptr& m : *metas)
                if (m->valueType() == "float" || m->valueType() == "double") {
                    name = m->getName();
                    break;
                }
            if (name.empty()) fail(path, "no float or double grid in the file");
        } else if (!file.hasGrid(name)) {
            fail(path, "no grid named \"" + name + "\"");
        }
        base = file.readGrid(name);
        file.close();
    } catch (const openvdb::Exception& e) {
        fail(path, std::string("cannot read the OpenVDB file (") + e.what() + ")");
    } catch (const std::ios_base::failure& e) {
        fail(path, std::string("cannot read the OpenVDB file (") + e.what() + ")");
    }
    // Float grids (also those saved as half floats: OpenVDB reads them back as float) and double
    // grids; vector and other grids are refused.
    const std::string type = base->valueType();
    if (type != "float" && type != "double")
        fail(path, "grid \"" + name + "\" holds " + type + " values, not float or double");
    const openvdb::math::Transform& xf = base->transform();
    if (!xf.isLinear()) fail(path, "grid \"" + name + "\" has a non-affine (" + xf.mapType() + ") transform");

    VdbDensity out;
    out.gridName = name;
    const openvdb::Mat4d M = xf.baseMap()->getAffineMap()->getMat4();  // row vectors: w = [i j k 1]·M
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) out.indexToWorld(r, c) = M(c, r);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            if (!std::isfinite(out.indexToWorld(r, c))) fail(path, "grid \"" + name + "\" has a non-finite transform");
    if (std::abs(out.indexToWorld.det3()) < 1e-30) fail(path, "grid \"" + name + "\" has a singular transform");

    out.grid = type == "float" ? bricksOf(*openvdb::gridPtrCast<openvdb::FloatGrid>(base), path, name)
                               : bricksOf(*openvdb::gridPtrCast<openvdb::DoubleGrid>(base), path, name);
    return out;
}

}  // namespace brume
