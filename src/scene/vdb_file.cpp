// OpenVDB → DensityGrid: the active voxels' bounding box copied into a dense, padded array
// (inactive voxels and everything outside are 0), and the grid's affine index → world map.
#include "brume/scene/vdb_file.h"

#include <cmath>
#include <mutex>

#include <openvdb/openvdb.h>

#include "brume/scene/gltf_loader.h"

namespace brume {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) { throw SceneError(path + ": " + problem); }

// Dense storage is 4 bytes a voxel over the bounding box: refuse what would not fit.
constexpr double kMaxDenseVoxels = 1u << 30;

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
            // The first float grid, by reading each grid's metadata only.
            openvdb::GridPtrVecPtr metas = file.readAllGridMetadata();
            for (const openvdb::GridBase::Ptr& m : *metas)
                if (m->valueType() == "float") {
                    name = m->getName();
                    break;
                }
            if (name.empty()) fail(path, "no float grid in the file");
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
    openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid) fail(path, "grid \"" + name + "\" holds " + base->valueType() + " values, not float");
    const openvdb::math::Transform& xf = grid->transform();
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

    auto dg = std::make_shared<DensityGrid>();
    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    int lo[3] = {0, 0, 0}, hi[3] = {-1, -1, -1};
    if (!box.empty()) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = box.min()[a];
            hi[a] = box.max()[a];
        }
        const double voxels = double(hi[0] - lo[0] + 3) * (hi[1] - lo[1] + 3) * (hi[2] - lo[2] + 3);
        if (voxels > kMaxDenseVoxels)
            fail(path, "grid \"" + name + "\" spans " + std::to_string(int64_t(voxels)) +
                           " voxels, more than the dense grid holds (2^30)");
    } else {
        lo[0] = lo[1] = lo[2] = 0;
        hi[0] = hi[1] = hi[2] = -1;  // no active voxel: an all-zero 2³ grid
    }
    auto acc = grid->getConstAccessor();
    std::string bad;
    dg->build(lo, hi, [&](int i, int j, int k) -> float {
        const openvdb::Coord c(i, j, k);
        if (!acc.isValueOn(c)) return 0.0f;
        const float v = acc.getValue(c);
        if (!(v >= 0) || !std::isfinite(v)) {
            if (bad.empty())
                bad = "grid \"" + name + "\" has " + (std::isnan(v) ? "a NaN" : std::isinf(v) ? "an infinite" : "a negative") +
                      " voxel value " + std::to_string(v) + " at (" + std::to_string(i) + ", " + std::to_string(j) + ", " +
                      std::to_string(k) + ")";
            return 0.0f;
        }
        return v;
    });
    if (!bad.empty()) fail(path, bad);
    out.grid = std::move(dg);
    return out;
}

}  // namespace brume
