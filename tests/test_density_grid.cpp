// Density grids and the heterogeneous medium built on them (scene/density_grid.h,
// scene/heterogeneous_medium.cpp):
//   - trilinear lookup reproduces linear fields, hits voxel values at integer points, is 0
//     outside the padded box;
//   - the brick majorants bound the density, and the majorant walk covers exactly the part
//     of a ray inside the grid's box, in contiguous pieces;
//   - delta tracking samples collision distances with density σt(t)·exp(−∫σt) (chi-square);
//   - ratio tracking's transmittance is unbiased (z test against the closed form);
//   - spectral tracking's weights are unbiased per channel, for one-hot and mixed channel
//     weights (z tests);
//   - the deterministic stand-in densities (brick means' optical depth) agree with their
//     formula, between sampleDistance and transit, and between a walk and its reverse;
//   - densityAt / sigmaSAt follow the grid's placement by a node.
//
// Statistical thresholds: z tests use |z| < 4.5 (two-sided false-failure probability
// 6.8e-6 each under normality; ~6e-4 summed over the 84 z tests of this file); chi-square
// tests use p > 1e-3. Every random number comes from a fixed seed, so a run that passes
// passes every time.
//
// Most statistical tests use one analytic field (linearGrid): voxel size 0.25 (indexToWorld
// scales by 0.25), active voxels i ∈ [0, 40], j, k ∈ [−2, 2], so the active box spans
// x ∈ [0, 10], y, z ∈ [−0.5, 0.5] in world units, with value ρ = 0.25 + 0.15·x + 0.1·y at every
// voxel. Trilinear interpolation reproduces it exactly inside the active box; along the line
// y = 0 (any |z| ≤ 0.5) it ramps linearly to 0 across the padding voxels at x = −0.25 and
// x = 10.25, which gives closed forms for the optical depth along any line y = const
// (rhoAxis, cumulativeAxis). On y = 0.5 the density reaches each brick's majorant (at the
// brick's far face); on y = 0 it stays 0.05 below it.
#include <catch2/catch.hpp>

#include <openvdb/openvdb.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "brume/math/mat4.h"
#include "brume/math/ray.h"
#include "brume/sampling/sampler.h"
#include "brume/scene/density_grid.h"
#include "brume/scene/vdb_file.h"
#include "support/scratch_files.h"
#include "brume/scene/medium.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {

constexpr double kZMax = 4.5;        // see the header comment
constexpr double kChi2Alpha = 1e-3;  // p-value threshold of the chi-square tests

// |a − b| ≤ rel·max(|a|, |b|).
bool closeRel(double a, double b, double rel) { return std::fabs(a - b) <= rel * std::max(std::fabs(a), std::fabs(b)); }

std::shared_ptr<DensityGrid> buildGrid(const int lo[3], const int hi[3], const std::function<float(int, int, int)>& f) {
    auto g = std::make_shared<DensityGrid>();
    g->build(lo, hi, f);
    return g;
}

// ---------------------------------------------------------------------------------------
// The analytic field (see the header comment)

constexpr double kVoxel = 0.25;
constexpr int kLinLo[3] = {0, -2, -2}, kLinHi[3] = {40, 2, 2};

double linearValue(double x, double y) { return 0.25 + 0.15 * x + 0.1 * y; }

std::shared_ptr<const DensityGrid> linearGrid() {
    static std::shared_ptr<const DensityGrid> g =
        buildGrid(kLinLo, kLinHi, [](int i, int j, int) { return float(linearValue(kVoxel * i, kVoxel * j)); });
    return g;
}

// Density on the line (x, y, z), y ∈ [−0.5, 0.5], |z| ≤ 0.5, at world x.
double rhoAxis(double x, double y = 0) {
    if (x <= -0.25 || x >= 10.25) return 0;
    if (x < 0) return (x + 0.25) / 0.25 * linearValue(0, y);
    if (x > 10) return (10.25 - x) / 0.25 * linearValue(10, y);
    return linearValue(x, y);
}

// ∫_{−∞}^{x} rhoAxis(·, y).
double cumulativeAxis(double x, double y = 0) {
    const double v0 = linearValue(0, y), v10 = linearValue(10, y);
    const double r0 = 0.5 * 0.25 * v0;  // the ramp below x = 0: height v0 over 0.25
    const double r10 = r0 + v0 * 10 + 0.075 * 100;
    if (x <= -0.25) return 0;
    if (x < 0) return 2 * v0 * (x + 0.25) * (x + 0.25);  // slope 4·v0
    if (x <= 10) return r0 + v0 * x + 0.075 * x * x;
    if (x < 10.25) return r10 + 2 * v10 * (0.0625 - (10.25 - x) * (10.25 - x));  // slope −4·v10
    return r10 + 2 * v10 * 0.0625;
}

Medium linearMedium(Spectrum sigmaS, Spectrum sigmaA, float scale = 1) {
    Medium m;
    m.name = "linear";
    m.sigmaS = sigmaS;
    m.sigmaA = sigmaA;
    m.density.grid = linearGrid();
    Mat4 s;
    s(0, 0) = s(1, 1) = s(2, 2) = kVoxel;
    m.density.indexToWorld = s;
    m.density.scale = scale;
    m.density.place(Mat4());
    return m;
}

// A ray along ±x on the line y, z = const; depth: ∫ρ (grid units, before k and scale)
// between parameters a ≤ b.
struct AxisRay {
    double ox, dir, y = 0, z = 0;
    Ray ray() const {
        Ray r;
        r.o = Vec3(float(ox), float(y), float(z));
        r.d = Vec3(float(dir), 0.0f, 0.0f);
        return r;
    }
    double x(double t) const { return ox + dir * t; }
    double rho(double t) const { return rhoAxis(x(t), y); }
    double depth(double a, double b) const { return std::fabs(cumulativeAxis(x(b), y) - cumulativeAxis(x(a), y)); }
};

// A random field with zero regions and a rotated, non-uniformly scaled placement (test 6).
std::shared_ptr<const DensityGrid> wavyGrid() {
    static const int lo[3] = {0, 0, 0}, hi[3] = {23, 19, 15};
    static std::shared_ptr<const DensityGrid> g = buildGrid(lo, hi, [](int i, int j, int k) {
        const double v = std::sin(0.4 * i) + 0.8 * std::cos(0.3 * j) + 0.5 * std::sin(0.5 * k + 1) + 0.3;
        return float(std::max(0.0, v));
    });
    return g;
}

Mat4 wavyIndexToWorld() {
    const double t[3] = {-1, 0.5, 2}, s[3] = {0.1, 0.12, 0.08};
    const double ax = 1 / std::sqrt(14.0), h = 0.35;
    const double q[4] = {ax * std::sin(h), 2 * ax * std::sin(h), 3 * ax * std::sin(h), std::cos(h)};
    return Mat4::fromTRS(t, q, s);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// 1. Lookup

TEST_CASE("density grid: trilinear lookup reproduces linear fields and voxel values, 0 outside", "[density]") {
    const int lo[3] = {-3, 2, 5}, hi[3] = {9, 12, 8};
    const double a = 2, b = 0.3, c = -0.1, d = 0.25;  // values 1.15 … 6.7, all positive
    auto field = [&](double x, double y, double z) { return a + b * x + c * y + d * z; };
    auto grid = buildGrid(lo, hi, [&](int i, int j, int k) { return float(field(i, j, k)); });
    REQUIRE(grid->n[0] == 15);
    REQUIRE(grid->n[1] == 13);
    REQUIRE(grid->n[2] == 6);
    CHECK(grid->activeVoxels == 13.0 * 11 * 4);
    CHECK(grid->maxValue == float(field(9, 2, 8)));

    // Integer index points: exactly the stored voxel value.
    for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
            for (int i = lo[0]; i <= hi[0]; ++i) {
                const float got = grid->lookup(grid->local(Vec3(float(i), float(j), float(k))));
                INFO("voxel " << i << " " << j << " " << k);
                REQUIRE(got == float(field(i, j, k)));
            }

    // Random points inside the active box: the linear field, to float rounding (values ≤ 6.7;
    // a float's relative spacing is 1.2e-7, so 2e-5·6.7 allows ~100 roundings).
    Rng rng(11, 1);
    const double tol = 2e-5 * 6.7;
    double worst = 0;
    for (int n = 0; n < 20000; ++n) {
        Vec3 p;
        for (int ax = 0; ax < 3; ++ax) p[ax] = float(lo[ax] + (hi[ax] - lo[ax]) * rng.next1D());
        const double err = std::fabs(grid->lookup(grid->local(p)) - field(p.x, p.y, p.z));
        worst = std::max(worst, err);
    }
    INFO("worst error " << worst);
    CHECK(worst < tol);

    // The padding shell: between the last active voxel and the zero padding voxel the value
    // falls linearly to 0 (x = lo − 1 + f: f·value(lo)).
    for (float f : {0.25f, 0.5f, 0.75f}) {
        const Vec3 p(float(lo[0] - 1) + f, 5.0f, 6.0f);
        CHECK(grid->lookup(grid->local(p)) == Approx(f * field(lo[0], 5, 6)).epsilon(1e-5));
        const Vec3 q(4.0f, 7.0f, float(hi[2] + 1) - f);
        CHECK(grid->lookup(grid->local(q)) == Approx(f * field(4, 7, hi[2])).epsilon(1e-5));
    }

    // Outside the padded box [lo − 1, hi + 1] (local [0, n − 1]): 0, on every side, including
    // the far faces themselves.
    for (int ax = 0; ax < 3; ++ax) {
        Vec3 inside(3.0f, 7.0f, 6.0f);
        for (float off : {1.0f, 1.001f, 1.5f, 7.0f, 1e6f}) {
            Vec3 below = inside, above = inside;
            below[ax] = float(lo[ax]) - off - 1e-3f;
            above[ax] = float(hi[ax]) + off;
            INFO("axis " << ax << " offset " << off);
            CHECK(grid->lookup(grid->local(below)) == 0.0f);
            CHECK(grid->lookup(grid->local(above)) == 0.0f);
        }
    }
    for (int n = 0; n < 20000; ++n) {
        Vec3 p;
        for (int ax = 0; ax < 3; ++ax) p[ax] = float(lo[ax] - 30 + (hi[ax] - lo[ax] + 60) * rng.next1D());
        const Vec3 q = grid->local(p);
        const bool outside = q.x < 0 || q.y < 0 || q.z < 0 || q.x >= grid->n[0] - 1 || q.y >= grid->n[1] - 1 ||
                             q.z >= grid->n[2] - 1;
        if (outside) REQUIRE(grid->lookup(q) == 0.0f);
    }
    CHECK(grid->lookup(Vec3(std::nanf(""), 1, 1)) == 0.0f);
}

// ---------------------------------------------------------------------------------------
// 2. Majorants

// Sparse storage: tests/data/sparse_blocks.vdb holds two 8³ blocks 2000 voxels apart and one
// active 128³ tile, in a box of 4224 × 128 × 128 voxels (71 million with the padding, 285 MB
// stored dense). Only the bricks the data reaches are kept (a block reaches 2³ bricks, the tile
// 17³), and every voxel reads back exactly, 0 between them.
TEST_CASE("density grid: sparse storage keeps the bricks the data reaches, not the box", "[density]") {
    const VdbDensity vdb = loadVdbDensity(std::string(BRUME_TEST_DATA) + "/sparse_blocks.vdb", "density");
    const DensityGrid& g = *vdb.grid;
    CHECK(g.activeVoxels == 2 * 512 + 128.0 * 128 * 128);
    auto at = [&](int i, int j, int k) { return g.lookup(g.local(Vec3(float(i), float(j), float(k)))); };
    for (int x0 : {0, 2000})
        for (int k = 0; k < 8; ++k)
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i) CHECK(at(x0 + i, j, k) == Approx(0.5 + (i + j + k) / 100.0).epsilon(1e-6));
    CHECK(at(4096, 0, 0) == 0.25f);
    CHECK(at(4223, 127, 127) == 0.25f);
    CHECK(at(4150, 64, 30) == 0.25f);
    CHECK(at(1000, 4, 4) == 0.0f);
    CHECK(at(8, 4, 4) == 0.0f);     // the first plane past a block
    CHECK(at(3000, 64, 64) == 0.0f);
    CHECK(at(4224, 64, 64) == 0.0f);  // past the tile
    CHECK(g.lookup(g.local(Vec3(7.5f, 4, 4))) == Approx(0.5 * (0.5 + 15 / 100.0)).epsilon(1e-6));  // fading out
    const size_t stored = g.voxels.size() / DensityGrid::kBrickVoxels;
    INFO(stored << " bricks stored, " << g.memoryBytes() << " bytes");
    CHECK(stored <= 2 * 8 + 17 * 17 * 17);
    CHECK(g.memoryBytes() < size_t(20) << 20);
}

// Empty space: a ray along the sparse grid's whole length (4224 voxels, 528 bricks) crosses
// its 30 empty regions (16³ bricks each) in one piece apiece. The pieces still tile the ray, and
// their majorants integrate to what the bricks' own give (compared on 20000 points, each
// looked up in its brick), bound the density and are 0 only where it is.
TEST_CASE("density grid: the walk crosses empty regions in one step", "[density]") {
    const VdbDensity vdb = loadVdbDensity(std::string(BRUME_TEST_DATA) + "/sparse_blocks.vdb", "density");
    const DensityGrid& g = *vdb.grid;
    REQUIRE(g.rn[0] == 34);  // 529 bricks (the padding's included)
    Rng rng(17, 3);
    for (int r = 0; r < 200; ++r) {
        // From before the box to past it, nearly along x, through the blocks or the tile.
        const Vec3 q0(-3.0f, 1.0f + 6.0f * rng.next1D(), 1.0f + 6.0f * rng.next1D());
        const Vec3 dq = normalize(Vec3(1.0f, 0.002f * (rng.next1D() - 0.5f), 0.002f * (rng.next1D() - 0.5f)));
        struct Piece {
            float ta, tb, m;
        };
        std::vector<Piece> ps;
        g.forEachMajorant(q0, dq, 0.0f, 5000.0f, [&](float ta, float tb, float m, float) {
            ps.push_back({ta, tb, m});
            return true;
        });
        INFO("ray " << r << ": " << ps.size() << " pieces");
        REQUIRE(!ps.empty());
        // 34 regions on x: 4 occupied (each block's, and the tile's 2) walked brick by brick
        // (up to 16 pieces each), the other 30 in one piece each. (Brick by brick: 529.)
        CHECK(ps.size() <= 4 * 16 + 30 + 2);
        for (size_t i = 1; i < ps.size(); ++i) REQUIRE(ps[i].ta == ps[i - 1].tb);
        auto pieceAt = [&](float t) {
            for (const Piece& p : ps)
                if (t >= p.ta && t < p.tb) return &p;
            return static_cast<const Piece*>(nullptr);
        };
        for (int k = 0; k < 100; ++k) {
            const float t = ps.front().ta + (ps.back().tb - ps.front().ta) * rng.next1D();
            const Piece* p = pieceAt(t);
            REQUIRE(p);
            const Vec3 q = q0 + dq * t;
            const float rho = g.lookup(q);
            CHECK(rho <= p->m + 1e-6f);
            if (p->m == 0.0f) CHECK(rho == 0.0f);
            // The brick's own majorant where the piece is not a merged empty region.
            if (p->m > 0) CHECK(p->m == g.majorant[g.brickAt(q)]);
        }
    }
}

// Grids as artists' tools write them, written here with OpenVDB itself: a float grid saved
// as half floats (saveFloatAsHalf), a double grid, a grid with no active voxel and one whose
// active voxels are all 0. Each loads; its values read back (half: to half precision; double:
// rounded to float); the empty ones are 0 everywhere.
TEST_CASE("density grid: half-float, double, empty and all-zero grids load", "[density]") {
    openvdb::initialize();
    brume::test::TempDir dir;
    auto v = [](int i, int j, int k) { return 0.5 + 0.01 * (i + 2 * j + 3 * k) + 1e-9; };
    auto write = [&](openvdb::GridBase::Ptr grid, const std::string& file) {
        grid->setName("density");
        grid->setTransform(openvdb::math::Transform::createLinearTransform(0.1));
        openvdb::io::File(dir / file).write({grid});
        return dir / file;
    };
    openvdb::FloatGrid::Ptr half = openvdb::FloatGrid::create(0.0f);
    openvdb::DoubleGrid::Ptr dbl = openvdb::DoubleGrid::create(0.0);
    openvdb::FloatGrid::Ptr zero = openvdb::FloatGrid::create(0.0f);
    for (int k = 0; k < 10; ++k)
        for (int j = 0; j < 10; ++j)
            for (int i = 0; i < 10; ++i) {
                half->tree().setValue(openvdb::Coord(i, j, k), float(v(i, j, k)));
                dbl->tree().setValue(openvdb::Coord(i, j, k), v(i, j, k));
                zero->tree().setValue(openvdb::Coord(i, j, k), 0.0f);
            }
    half->setSaveFloatAsHalf(true);
    const VdbDensity h = loadVdbDensity(write(half, "half.vdb"), "density");
    const VdbDensity d = loadVdbDensity(write(dbl, "double.vdb"), "");  // (the first grid: double is taken)
    const VdbDensity e = loadVdbDensity(write(openvdb::FloatGrid::create(0.0f), "empty.vdb"), "density");
    const VdbDensity z = loadVdbDensity(write(zero, "zero.vdb"), "density");
    CHECK(h.grid->activeVoxels == 1000);
    CHECK(d.grid->activeVoxels == 1000);
    CHECK(d.gridName == "density");
    for (int k = 0; k < 10; ++k)
        for (int j = 0; j < 10; ++j)
            for (int i = 0; i < 10; ++i) {
                const Vec3 p = Vec3(float(i), float(j), float(k));
                CHECK(h.grid->lookup(h.grid->local(p)) == Approx(v(i, j, k)).epsilon(1e-3));
                CHECK(d.grid->lookup(d.grid->local(p)) == float(v(i, j, k)));
            }
    for (const VdbDensity* g : {&e, &z}) {
        CHECK(g->grid->activeVoxels == 0);
        CHECK(g->grid->maxValue == 0);
        CHECK(g->grid->lookup(g->grid->local(Vec3(3, 4, 5))) == 0);
        CHECK(g->grid->voxels.empty());
    }
}

TEST_CASE("density grid: majorants bound the density and the walk covers the box", "[density]") {
    // Active 18 × 20 × 7 voxels (padded 20 × 22 × 9: 3 × 3 × 1 bricks, the last ones partial);
    // random values with 30% zeros, and all of brick x = 0 (local q.x ≤ 8, index i ≤ 2) zero.
    const int lo[3] = {-5, 3, 0}, hi[3] = {12, 22, 6};
    // (A function of the voxel: bricks share their faces, so a voxel may be asked twice.)
    auto grid = buildGrid(lo, hi, [&](int i, int j, int k) {
        Rng valueRng(21 + uint64_t((i + 64) * 4096 + (j + 64) * 64 + k), 2);
        const float u = valueRng.next1D(), v = valueRng.next1D();
        return (i <= 2 || u < 0.3f) ? 0.0f : v;
    });
    const DensityGrid& g = *grid;
    const int B = DensityGrid::kBrick;
    REQUIRE(g.bn[0] == 3);
    REQUIRE(g.bn[1] == 3);
    REQUIRE(g.bn[2] == 1);
    auto brickMajorant = [&](int bx, int by, int bz) { return g.majorant[(size_t(bz) * g.bn[1] + by) * g.bn[0] + bx]; };
    CHECK(brickMajorant(0, 0, 0) == 0.0f);
    CHECK(brickMajorant(0, 2, 0) == 0.0f);

    Rng rng(22, 3);
    // Every brick: lookups anywhere in it (its part of [0, n − 1]) stay below its majorant.
    for (int bz = 0; bz < g.bn[2]; ++bz)
        for (int by = 0; by < g.bn[1]; ++by)
            for (int bx = 0; bx < g.bn[0]; ++bx) {
                const int b[3] = {bx, by, bz};
                const float m = brickMajorant(bx, by, bz);
                float seen = 0;
                for (int n = 0; n < 4000; ++n) {
                    Vec3 q;
                    for (int ax = 0; ax < 3; ++ax) {
                        const float q0 = float(b[ax] * B), q1 = float(std::min((b[ax] + 1) * B, g.n[ax] - 1));
                        q[ax] = q0 + (q1 - q0) * rng.next1D();
                    }
                    seen = std::max(seen, g.lookup(q));
                }
                INFO("brick " << bx << " " << by << " " << bz);
                CHECK(seen <= m);
                // ...and it is not wildly loose: the brick's largest voxel is a lookup point.
                // The brick mean (the stand-in densities' optical depth) is the mean of the
                // same voxels: 0 exactly where the majorant is 0.
                float vmaxVox = 0;
                double sum = 0, count = 0;
                for (int k = bz * B; k <= std::min((bz + 1) * B, g.n[2] - 1); ++k)
                    for (int j = by * B; j <= std::min((by + 1) * B, g.n[1] - 1); ++j)
                        for (int i = bx * B; i <= std::min((bx + 1) * B, g.n[0] - 1); ++i) {
                            vmaxVox = std::max(vmaxVox, g.at(i, j, k));
                            sum += g.at(i, j, k);
                            count += 1;
                        }
                CHECK(m == vmaxVox);
                const float mean = g.mean[(size_t(bz) * g.bn[1] + by) * g.bn[0] + bx];
                CHECK(mean == Approx(sum / count).epsilon(1e-6));
                CHECK((mean > 0) == (m > 0));
                CHECK(mean <= m);
            }

    // Random lines q0 + t·dq over [t0, t1].
    const double slack = 1e-4;  // density difference allowed at a piece's ends (float rounding of q)
    long pieces = 0, emptyRays = 0, checkedPoints = 0;
    for (int r = 0; r < 20000; ++r) {
        const int kind = r % 5;
        Vec3 q0, dq;
        for (int ax = 0; ax < 3; ++ax) q0[ax] = -10.0f + (g.n[ax] + 19.0f) * rng.next1D();
        if (kind == 1)  // start inside the box
            for (int ax = 0; ax < 3; ++ax) q0[ax] = (g.n[ax] - 1.0f) * rng.next1D();
        // A direction of random length (the ray parameter is not the local distance).
        const float len = 0.3f + 3.0f * rng.next1D();
        if (kind == 2) {  // axis-aligned
            const int ax = int(rng.next1D() * 3) % 3;
            dq = Vec3(0.0f);
            dq[ax] = rng.next1D() < 0.5f ? -len : len;
            for (int o = 0; o < 3; ++o)
                if (o != ax) q0[o] = (g.n[o] - 1.0f) * (0.02f + 0.96f * rng.next1D());  // mostly inside the slab
        } else {
            const float z = 1 - 2 * rng.next1D(), phi = 2 * kPi * rng.next1D(), s = std::sqrt(std::max(0.0f, 1 - z * z));
            dq = Vec3(s * std::cos(phi), s * std::sin(phi), z) * len;
            if (kind == 3) dq[int(rng.next1D() * 3) % 3] = 0;  // one zero component
            if (kind == 4 && r % 2) {  // aimed at a random point of the box
                Vec3 target;
                for (int ax = 0; ax < 3; ++ax) target[ax] = (g.n[ax] - 1.0f) * rng.next1D();
                dq = normalize(target - q0) * len;
            }
        }
        const float t0 = -5.0f + 10.0f * rng.next1D();
        const float t1 = (r % 7 == 0) ? kInfinity : t0 + 60.0f * rng.next1D();

        // Independent slab test, in double.
        double sa = t0, sb = t1;
        bool miss = false;
        for (int ax = 0; ax < 3; ++ax) {
            const double o = q0[ax], d = dq[ax], hiB = g.n[ax] - 1;
            if (d == 0) {
                if (o < 0 || o > hiB) miss = true;
                continue;
            }
            double tl = (0 - o) / d, th = (hiB - o) / d;
            if (tl > th) std::swap(tl, th);
            sa = std::max(sa, tl);
            sb = std::min(sb, th);
        }
        if (miss) sb = sa - 1;

        struct Piece {
            float ta, tb, m, mean;
        };
        std::vector<Piece> ps;
        g.forEachMajorant(q0, dq, t0, t1, [&](float ta, float tb, float m, float mean) {
            ps.push_back({ta, tb, m, mean});
            return true;
        });
        pieces += long(ps.size());
        const double tol = 1e-5 * (1 + std::fabs(sa) + (std::isfinite(sb) ? std::fabs(sb) : 0.0));
        INFO("ray " << r << " q0 (" << q0.x << ", " << q0.y << ", " << q0.z << ") dq (" << dq.x << ", " << dq.y << ", "
                    << dq.z << ") t0 " << t0 << " t1 " << t1 << " slab [" << sa << ", " << sb << "] pieces "
                    << ps.size());
        if (sb - sa > tol) {
            REQUIRE(!ps.empty());
            CHECK(std::fabs(ps.front().ta - sa) <= tol);
            CHECK(std::fabs(ps.back().tb - sb) <= tol);
        } else {
            ++emptyRays;
            double total = 0;
            for (const Piece& p : ps) total += p.tb - p.ta;
            CHECK(total <= 2 * tol);
        }
        for (size_t i = 0; i < ps.size(); ++i) {
            const Piece& p = ps[i];
            REQUIRE(p.ta < p.tb);
            REQUIRE(std::isfinite(p.tb));
            if (i > 0) REQUIRE(p.ta == ps[i - 1].tb);  // contiguous
            // The piece lies in one brick: its majorant is that of the brick at its midpoint.
            const float tm = 0.5f * (p.ta + p.tb);
            const Vec3 qm = q0 + dq * tm;
            if ((p.tb - p.ta) * len > 1e-3f) {
                int cell[3];
                for (int ax = 0; ax < 3; ++ax) cell[ax] = std::min(std::max(int(std::floor(qm[ax] / B)), 0), g.bn[ax] - 1);
                const size_t bi = (size_t(cell[2]) * g.bn[1] + cell[1]) * g.bn[0] + cell[0];
                CHECK(p.m == g.majorant[bi]);
                CHECK(p.mean == g.mean[bi]);
            }
            // Majorant ≥ density at points of the piece (its ends included).
            for (int s = 0; s < 12; ++s) {
                const float u = s == 0 ? 0.0f : (s == 1 ? 1.0f : rng.next1D());
                const float t = p.ta + (p.tb - p.ta) * u;
                const float rho = g.lookup(q0 + dq * t);
                ++checkedPoints;
                if (!(rho <= p.m + slack)) {
                    INFO("piece " << i << " [" << p.ta << ", " << p.tb << "] majorant " << p.m << " t " << t << " density "
                                  << rho);
                    CHECK(rho <= p.m + slack);
                }
            }
        }
        // Outside the covered range (but within [t0, t1]) the density is 0.
        const double ca = ps.empty() ? sa : ps.front().ta, cb = ps.empty() ? sa : ps.back().tb;
        const double end = std::isfinite(t1) ? double(t1) : cb + 50.0;
        for (int s = 0; s < 8; ++s) {
            const double t = t0 + (end - t0) * rng.next1D();
            if (t > ca - 1e-3 && t < cb + 1e-3) continue;
            const float rho = g.lookup(q0 + dq * float(t));
            if (rho != 0.0f) {
                INFO("uncovered t " << t << " density " << rho);
                CHECK(rho == 0.0f);
            }
        }
    }
    std::printf("[majorant walk] %ld pieces, %ld rays missing the box, %ld points checked\n", pieces, emptyRays,
                checkedPoints);
    CHECK(emptyRays > 1000);  // both kinds of rays were exercised
    CHECK(pieces > 10000);

    // f returning false stops the walk.
    int calls = 0;
    g.forEachMajorant(Vec3(-1.0f, 5.0f, 4.0f), Vec3(1.0f, 0.0f, 0.0f), 0.0f, 100.0f, [&](float, float, float, float) {
        ++calls;
        return false;
    });
    CHECK(calls == 1);
    calls = 0;
    g.forEachMajorant(Vec3(-1.0f, 5.0f, 4.0f), Vec3(1.0f, 0.0f, 0.0f), 0.0f, 100.0f, [&](float, float, float, float) {
        ++calls;
        return true;
    });
    CHECK(calls == 3);  // x crosses 3 bricks
}

// ---------------------------------------------------------------------------------------
// 3. Delta tracking

TEST_CASE("heterogeneous medium: delta tracking samples collisions with density sigma_t * T", "[density][chi2]") {
    // Grey: σs = 0.7, σa = 0.3 per unit density, so σt(x) = ρ(x). Three rays: along +x from
    // x = −1 (empty space, the ramp into the grid, then the linear part) to x = 5.5
    // (P_pass = e^−3.675 ≈ 0.025); along −x from x = 11 through the upper ramp to x = 6
    // (P_pass ≈ 0.0024); along +x on y = 0.3 (between voxel rows) from x = 0.5 to 6.5, inside
    // the active region (P_pass ≈ 0.008).
    // (Each flight is a function of (ray, t0, t1, uDistance), and uDistance has 24 random bits,
    // so with one ray per case the samples are independent only while N ≪ 2^24: at N = 1e7 the
    // repeats inflate chi2 by ~30%. N = 2e5 repeats ~1%.)
    const Medium med = linearMedium(Spectrum(0.7f), Spectrum(0.3f));
    struct Case {
        AxisRay ar;
        float t0, t1;
    };
    const Case cases[] = {{{-1.5, 1}, 0.5f, 7.0f}, {{11.0, -1}, 0.0f, 5.0f}, {{0.3, 1, 0.3}, 0.2f, 6.2f}};
    const long N = 200000;
    const int bins = 64;
    int caseIndex = 0;
    for (const Case& cs : cases) {
        const Ray ray = cs.ar.ray();
        std::vector<double> observed(bins + 1, 0.0), expected(bins + 1, 0.0);
        const double L = cs.t1 - cs.t0;
        for (int b = 0; b < bins; ++b) {
            const double a = cs.t0 + L * b / bins, c = cs.t0 + L * (b + 1) / bins;
            expected[b] = N * (std::exp(-cs.ar.depth(cs.t0, a)) - std::exp(-cs.ar.depth(cs.t0, c)));
        }
        expected[bins] = N * std::exp(-cs.ar.depth(cs.t0, cs.t1));
        Rng rng(31 + caseIndex, 4);
        long badWeight = 0, emptyCollision = 0, badT = 0;
        for (long n = 0; n < N; ++n) {
            const MediumSample ms =
                med.sampleDistance(ray, cs.t0, cs.t1, rng.next1D(), rng.next1D(), Spectrum(1.0f / 3), false);
            if (ms.scattered) {
                if (!(ms.t >= cs.t0 && ms.t < cs.t1)) {
                    ++badT;
                    continue;
                }
                const int b = std::min(bins - 1, int((ms.t - cs.t0) / L * bins));
                observed[b] += 1;
                for (int c = 0; c < 3; ++c)
                    if (std::fabs(ms.weight[c] - 0.7f) > 1e-6f) ++badWeight;
                if (!(med.densityAt(ray.at(ms.t)) > 0)) ++emptyCollision;
            } else {
                if (ms.t != cs.t1) ++badT;
                observed[bins] += 1;
                for (int c = 0; c < 3; ++c)
                    if (ms.weight[c] != 1.0f) ++badWeight;
            }
        }
        const ChiSquareResult r = chiSquareTest(observed, expected, 5.0, [&](int b) {
            return b == bins ? std::string("pass") : "t in [" + std::to_string(cs.t0 + L * b / bins) + ", " +
                                                          std::to_string(cs.t0 + L * (b + 1) / bins) + ")";
        });
        std::printf("[delta tracking] case %d: chi2 = %.2f dof = %d p = %.4f, passes %.0f (expected %.1f)\n", caseIndex,
                    r.chi2, r.dof, r.pValue, observed[bins], expected[bins]);
        INFO("case " << caseIndex << "\n" << r.table);
        CHECK(badT == 0);
        CHECK(badWeight == 0);
        CHECK(emptyCollision == 0);
        CHECK(r.pValue > kChi2Alpha);
        ++caseIndex;
    }
}

// ---------------------------------------------------------------------------------------
// 4. Ratio tracking

TEST_CASE("heterogeneous medium: ratio tracking transmittance is unbiased and in [0, 1]", "[density]") {
    // The random stream is hashed from the ray's bits, so every sample uses its own ray: the
    // origin is jittered in z (|z| ≤ 0.3; the field does not depend on z inside the active
    // box) and moved along the ray with t0, t1 shifted to keep the same segment.
    struct Case {
        const char* name;
        Spectrum sigmaS, sigmaA;
        float scale;
        Vec3 a, dir;    // segment start (z replaced by the jitter) and unit direction
        double length;  // +∞: to infinity (the walk stops where the ray leaves the grid)
        double depth;   // ∫ρ over the segment, closed form
    };
    const double diagLen = std::sqrt(9.0 * 9.0 + 0.8 * 0.8);
    const Case cases[] = {
        {"grey, +x, x in [-1, 5.5]", Spectrum(0.7f), Spectrum(0.3f), 1.0f, Vec3(-1, 0, 0), Vec3(1, 0, 0), 6.5,
         cumulativeAxis(5.5) - cumulativeAxis(-1)},
        {"grey, scale 0.3, +x from x = 4 to infinity", Spectrum(0.7f), Spectrum(0.3f), 0.3f, Vec3(4, 0, 0), Vec3(1, 0, 0),
         kInfinity, cumulativeAxis(20) - cumulativeAxis(4)},
        {"coloured, scale 0.5, -x, x in [3, 11]", Spectrum(0.25f, 0.5f, 1.0f), Spectrum(0.0f), 0.5f, Vec3(11, 0, 0),
         Vec3(-1, 0, 0), 8.0, cumulativeAxis(11) - cumulativeAxis(3)},
        {"coloured, diagonal (0.5, -0.4) to (9.5, 0.4)", Spectrum(0.1f, 0.2f, 0.05f), Spectrum(0.1f, 0.0f, 0.3f), 1.0f,
         Vec3(0.5f, -0.4f, 0), Vec3(float(9 / diagLen), float(0.8 / diagLen), 0), diagLen,
         diagLen * 0.5 * (linearValue(0.5, -0.4) + linearValue(9.5, 0.4))},
    };
    const long N = 250000;
    int caseIndex = 0;
    for (const Case& cs : cases) {
        Medium med = linearMedium(cs.sigmaS, cs.sigmaA, cs.scale);
        const Spectrum k = med.sigmaT() * cs.scale;
        Rng rng(41 + caseIndex, 5);
        RunningStats stats[3];
        long outOfRange = 0, transmittanceMismatch = 0, flagMismatch = 0;
        for (long n = 0; n < N; ++n) {
            const float shift = 0.5f * rng.next1D();
            Ray ray;
            ray.o = cs.a - cs.dir * shift;
            ray.o.z = -0.3f + 0.6f * rng.next1D();
            ray.d = cs.dir;
            const float t0 = shift, t1 = std::isfinite(cs.length) ? float(shift + cs.length) : kInfinity;
            const MediumTransit tr = med.transit(ray, t0, t1, false, false);
            for (int c = 0; c < 3; ++c) {
                stats[c].add(tr.T[c]);
                if (!(tr.T[c] >= 0 && tr.T[c] <= 1)) ++outOfRange;
            }
            if (n % 16 == 0) {
                const Spectrum T2 = med.transmittance(ray, t0, t1);
                if (!(T2.x == tr.T.x && T2.y == tr.T.y && T2.z == tr.T.z)) ++transmittanceMismatch;
                const MediumTransit tr2 = med.transit(ray, t0, t1, true, true);
                if (!(tr2.T.x == tr.T.x && tr2.T.y == tr.T.y && tr2.T.z == tr.T.z)) ++flagMismatch;
            }
        }
        INFO(cs.name);
        CHECK(outOfRange == 0);
        CHECK(transmittanceMismatch == 0);
        CHECK(flagMismatch == 0);
        for (int c = 0; c < 3; ++c) {
            const double ref = std::exp(-double(k[c]) * cs.depth);
            const double z = zScore(stats[c].mean(), ref, stats[c].standardError());
            std::printf("[ratio tracking] %-45s c%d: T = %.5f +- %.5f, exact %.5f, z = %+.2f\n", cs.name, c,
                        stats[c].mean(), stats[c].standardError(), ref, z);
            INFO("channel " << c << " mean " << stats[c].mean() << " se " << stats[c].standardError() << " exact " << ref);
            CHECK(std::fabs(z) < kZMax);
            // Guard against a degenerate estimator (e.g. always the exact value of a wrong τ).
            CHECK(stats[c].standardError() < 0.05 * ref);
        }
        ++caseIndex;
    }
}

// Bounded work: at the loader's density limit (optical depth 10^4 across one voxel,
// gltf_media.cpp) a shadow ray through the whole grid draws a few hundred tentative
// collisions (25000 without the roulette): ratio tracking's roulette ends the estimate once
// every channel is below 1/16. What remains is the entry into the
// grid, where the trilinear density rises from 0 under a brick majorant m: T falls like
// exp(−μ·∫ρ/m), so the steps before it is small grow as √(optical depth per voxel) (~250
// here). (Without the roulette T fell to 0 only through the subnormals and then walked the
// rest of each brick: a 32 × 24 render of single_gradient at the limit took 93 s against 0.3 s.)
TEST_CASE("heterogeneous medium: ratio tracking's work is bounded at the density limit", "[density]") {
    const Medium probe = linearMedium(Spectrum(0.7f), Spectrum(0.3f));
    const float scale = float(1e4 / (1.0 * probe.density.grid->maxValue * kVoxel));  // σt = 1 per unit density
    const Medium med = linearMedium(Spectrum(0.7f), Spectrum(0.3f), scale);
    const long N = 2000;
    double steps = 0;
    uint32_t most = 0;
    long outOfRange = 0;
    Rng rng(7, 3);
    for (long n = 0; n < N; ++n) {
        Ray ray;
        ray.o = Vec3(-1.0f - rng.next1D(), -0.4f + 0.8f * rng.next1D(), -0.3f + 0.6f * rng.next1D());
        ray.d = Vec3(1, 0, 0);
        const MediumTransit tr = med.transit(ray, 0.0f, 13.0f, false, false);  // across the whole grid
        steps += tr.steps;
        most = std::max(most, tr.steps);
        for (int c = 0; c < 3; ++c)
            if (!(tr.T[c] >= 0 && tr.T[c] <= 1)) ++outOfRange;
    }
    INFO("mean " << steps / N << " tentative collisions a ray, most " << most);
    CHECK(outOfRange == 0);
    CHECK(steps / N < 1000);
    CHECK(most < 4000);
}

// ---------------------------------------------------------------------------------------
// 5. Spectral tracking

TEST_CASE("heterogeneous medium: spectral tracking weights are unbiased per channel", "[density]") {
    // σs = (0.5, 1, 2)·0.5 per unit density, no absorption; rays along +x from x = −1 to
    // x = 5.5 (on y = 0: T = 0.40, 0.16, 0.025), on the line y = 0 (density ≥ 0.05 below the
    // majorant) and on y = 0.5 (density reaching the majorant at every brick's far face, where
    // a one-hot real/null choice would make the other channels' null weights unbounded). For
    // channel weights w (one-hot on each channel, and 1/3 each), and every channel c:
    //   E[weight_c·1{collision}·h(t)] = ∫ h(t)·σs_c(t)·T_c(t) dt   (h = 1 and h = (t − t0)/L)
    //   E[weight_c·1{pass}]           = T_c(t1).
    const Medium med = linearMedium(Spectrum(0.25f, 0.5f, 1.0f), Spectrum(0.0f));
    const Spectrum k = med.sigmaT(), ks = med.sigmaS;
    const float t0 = 0.5f, t1 = 7.0f;
    const double L = t1 - t0;
    auto h2 = [&](double t) { return (t - t0) / L; };
    const Spectrum weightings[] = {heroChannel(0), heroChannel(1), heroChannel(2), Spectrum(1.0f / 3)};
    const char* names[] = {"hero 0", "hero 1", "hero 2", "mixed"};
    const long N = 60000;
    for (int li = 0; li < 2; ++li) {
    const AxisRay ar{-1.5, 1, li == 0 ? 0.0 : 0.5};
    const Ray ray = ar.ray();
    double refScatter[3], refScatterH[3], refPass[3];
    for (int c = 0; c < 3; ++c) {
        auto integrand = [&](double t, bool weighted) {
            return (weighted ? h2(t) : 1.0) * ks[c] * ar.rho(t) * std::exp(-k[c] * ar.depth(t0, t));
        };
        refScatter[c] = integrate1D([&](double t) { return integrand(t, false); }, t0, t1, 1e-12, 1e-9, 64);
        refScatterH[c] = integrate1D([&](double t) { return integrand(t, true); }, t0, t1, 1e-12, 1e-9, 64);
        refPass[c] = std::exp(-k[c] * ar.depth(t0, t1));
        // No absorption: every particle either scatters or passes (checks the closed forms).
        CHECK(refScatter[c] + refPass[c] == Approx(1.0).epsilon(1e-7));
    }
    for (int wi = 0; wi < 4; ++wi) {
        Rng rng(51 + wi + 10 * li, 6);
        RunningStats scatter[3], scatterH[3], pass[3];
        long bad = 0;
        double maxWeight = 0;
        for (long n = 0; n < N; ++n) {
            const MediumSample ms = med.sampleDistance(ray, t0, t1, rng.next1D(), rng.next1D(), weightings[wi], false);
            for (int c = 0; c < 3; ++c) {
                const double w = ms.weight[c];
                if (!(std::isfinite(w) && w >= 0)) ++bad;
                maxWeight = std::max(maxWeight, w);
                scatter[c].add(ms.scattered ? w : 0.0);
                scatterH[c].add(ms.scattered ? w * h2(ms.t) : 0.0);
                pass[c].add(ms.scattered ? 0.0 : w);
            }
        }
        std::printf("[spectral tracking] y = %.1f %-6s largest weight %.3g\n", ar.y, names[wi], maxWeight);
        INFO("y = " << ar.y);
        INFO(names[wi]);
        CHECK(bad == 0);
        for (int c = 0; c < 3; ++c) {
            const struct {
                const char* what;
                const RunningStats& s;
                double ref;
            } checks[] = {{"scatter", scatter[c], refScatter[c]},
                          {"scatter*h", scatterH[c], refScatterH[c]},
                          {"pass", pass[c], refPass[c]}};
            for (const auto& q : checks) {
                const double z = zScore(q.s.mean(), q.ref, q.s.standardError());
                std::printf("[spectral tracking] y = %.1f %-6s c%d %-9s: %.5f +- %.5f, exact %.5f, z = %+.2f\n", ar.y,
                            names[wi], c, q.what, q.s.mean(), q.s.standardError(), q.ref, z);
                INFO("channel " << c << " " << q.what << " mean " << q.s.mean() << " se " << q.s.standardError()
                                << " exact " << q.ref);
                CHECK(std::fabs(z) < kZMax);
                CHECK(q.s.standardError() < 0.1 * q.ref);  // the test has power
            }
        }
    }
    }
}

// ---------------------------------------------------------------------------------------
// 6. Stand-in densities

TEST_CASE("heterogeneous medium: stand-in densities agree across strategies and directions", "[density]") {
    // A wavy field with zero regions, rotated and non-uniformly scaled; random rays through
    // it. For every sampleDistance outcome at t (a collision or t1):
    //   fwd_c = k̄·ρ(x_t)·exp(−k̄·τ̃) (collision) or exp(−k̄·τ̃) (pass), τ̃ = ∫_{t0}^{t} ρ̃
    //   with ρ̃ the mean of each brick crossed (recomputed here with the majorant walk) and k̄
    //   the mean of the channels' extinction coefficients: the same in every channel;
    //   rev_c likewise with ρ(x_t0) if t0 is a medium point;
    //   transit over [t0, t] gives the same fwd and rev; pdf = fwd_c, the same for every c;
    //   transit over the reversed ray (from x_t back to x_t0) gives them swapped.
    // Tolerances: 1e-5 relative between sampleDistance, transit and the formula on the same
    // ray (seen: < 1e-6). The reversed ray is the same line only to float rounding (its origin
    // ray.at(t) is rounded, ~1e-6 voxels), so (a) its densities use ρ looked up at its own end
    // points, which agree with the forward ones to 1e-4 absolute, and (b) its brick-face
    // crossings move by ~1e-6/|dq_a| in t, large where the ray grazes a face (dq_a ≈ 0.05
    // voxels per unit t moved a crossing by 2e-5, changing exp(−k·τ̃) by 1.5e-5), so the
    // optical depth both ways is compared to 1e-4 relative.
    const double rel = 1e-5, relReversed = 1e-4, rhoTol = 1e-4;
    struct MediumCase {
        const char* name;
        Spectrum sigmaS, sigmaA;
        float scale;
    };
    const MediumCase media[] = {{"grey", Spectrum(1.5f), Spectrum(0.5f), 1.0f},
                                {"coloured", Spectrum(0.5f, 1.0f, 2.0f), Spectrum(0.25f, 0.0f, 0.5f), 0.8f}};
    int mi = 0;
    for (const MediumCase& mc : media) {
        Medium med;
        med.sigmaS = mc.sigmaS;
        med.sigmaA = mc.sigmaA;
        med.density.grid = wavyGrid();
        med.density.indexToWorld = wavyIndexToWorld();
        med.density.scale = mc.scale;
        med.density.place(Mat4());
        const DensityGrid& g = *med.density.grid;
        const Spectrum k3 = med.sigmaT() * mc.scale;
        const Spectrum k(float((double(k3.x) + k3.y + k3.z) / 3));  // grey stand-ins
        Rng rng(61 + mi, 7);
        long collisions = 0, passes = 0, failures = 0;
        double worstFormula = 0, worstTransit = 0, worstReverse = 0;
        for (int n = 0; n < 3000; ++n) {
            // A ray between two random points of the (slightly enlarged) index box.
            Vec3 pa, pb;
            for (int ax = 0; ax < 3; ++ax) {
                pa[ax] = -2.0f + (g.n[ax] + 1.0f) * rng.next1D();
                pb[ax] = -2.0f + (g.n[ax] + 1.0f) * rng.next1D();
            }
            const Vec3 wa = med.density.indexToWorld.point(pa), wb = med.density.indexToWorld.point(pb);
            const float len = length(wb - wa);
            if (len < 0.2f) continue;
            Ray ray;
            ray.o = wa;
            ray.d = normalize(wb - wa);
            const float t0 = 0.3f * len * rng.next1D(), t1 = len * (0.7f + 0.5f * rng.next1D());
            const bool startIsPoint = rng.next1D() < 0.5f;
            Spectrum w;
            const int wk = n % 3;
            if (wk == 0) w = heroChannel(n / 3 % 3);
            else if (wk == 1) w = Spectrum(1.0f / 3);
            else {
                w = Spectrum(rng.next1D(), rng.next1D(), rng.next1D()) + Spectrum(0.01f);
                w /= (w.x + w.y + w.z);
            }
            const MediumSample ms = med.sampleDistance(ray, t0, t1, rng.next1D(), rng.next1D(), w, startIsPoint);
            (ms.scattered ? collisions : passes) += 1;
            const float tEnd = ms.scattered ? ms.t : t1;

            // τ̃ over [t0, tEnd] from the majorant walk's brick means.
            const Vec3 q0 = med.density.worldToLocal.point(ray.o), dq = med.density.worldToLocal.vector(ray.d);
            double tauBar = 0;
            g.forEachMajorant(q0, dq, t0, tEnd, [&](float ta, float tb, float, float mean) {
                tauBar += double(mean) * (tb - ta);
                return true;
            });
            const double rhoEnd = g.lookup(q0 + dq * tEnd), rhoStart = g.lookup(q0 + dq * t0);
            Channels fwd, rev;
            for (int c = 0; c < 3; ++c) {
                const double e = std::exp(-double(k[c]) * tauBar);
                fwd[c] = ms.scattered ? k[c] * rhoEnd * e : e;
                rev[c] = startIsPoint ? k[c] * rhoStart * e : e;
            }
            const MediumTransit tr = med.transit(ray, t0, tEnd, startIsPoint, ms.scattered);
            Ray back;
            back.o = ray.at(tEnd);
            back.d = -ray.d;
            const MediumTransit trBack = med.transit(back, 0.0f, tEnd - t0, ms.scattered, startIsPoint);
            const Vec3 qb0 = med.density.worldToLocal.point(back.o), dqb = med.density.worldToLocal.vector(back.d);
            const double rhoBackStart = g.lookup(qb0), rhoBackEnd = g.lookup(qb0 + dqb * (tEnd - t0));
            Channels backFwd, backRev;
            for (int c = 0; c < 3; ++c) {
                const double e = std::exp(-double(k[c]) * tauBar);
                backFwd[c] = startIsPoint ? k[c] * rhoBackEnd * e : e;
                backRev[c] = ms.scattered ? k[c] * rhoBackStart * e : e;
            }
            bool ok = std::fabs(rhoBackStart - rhoEnd) <= rhoTol && std::fabs(rhoBackEnd - rhoStart) <= rhoTol;
            for (int c = 0; c < 3; ++c) {
                auto relErr = [](double a, double b) {
                    const double s = std::max(std::fabs(a), std::fabs(b));
                    return s > 0 ? std::fabs(a - b) / s : 0.0;
                };
                const double eF = std::max(relErr(ms.fwd[c], fwd[c]), relErr(ms.rev[c], rev[c]));
                const double eT = std::max(relErr(ms.fwd[c], tr.fwd[c]), relErr(ms.rev[c], tr.rev[c]));
                const double eR = std::max(relErr(backRev[c], trBack.rev[c]), relErr(backFwd[c], trBack.fwd[c]));
                worstFormula = std::max(worstFormula, eF);
                worstTransit = std::max(worstTransit, eT);
                worstReverse = std::max(worstReverse, eR);
                if (!(eF <= rel && eT <= rel && eR <= relReversed)) ok = false;
            }
            if (ms.scattered && !(rhoEnd > 0)) ok = false;  // collisions only where there is density
            // Grey stand-ins: whatever channel weights w drove the real/null choice, the
            // sampled mixture's density is the (common) stand-in.
            if (!closeRel(ms.pdf, ms.fwd[0], 1e-12) || ms.fwd[0] != ms.fwd[1] || ms.fwd[1] != ms.fwd[2]) ok = false;
            if (!ok && failures++ < 5) {
                std::ostringstream msg;
                msg.precision(9);
                msg << "rho: end " << rhoEnd << " (reversed " << rhoBackStart << "), start " << rhoStart << " (reversed "
                    << rhoBackEnd << ")\n";
                msg << mc.name << " ray " << n << " o (" << ray.o.x << ", " << ray.o.y << ", " << ray.o.z << ") d ("
                    << ray.d.x << ", " << ray.d.y << ", " << ray.d.z << ") t0 " << t0 << " t1 " << t1 << " startIsPoint "
                    << startIsPoint << " scattered " << ms.scattered << " t " << ms.t << " pdf " << ms.pdf << "\n";
                for (int c = 0; c < 3; ++c)
                    msg << "c" << c << ": fwd " << ms.fwd[c] << " formula " << fwd[c] << " transit " << tr.fwd[c]
                        << " reverse-transit rev " << trBack.rev[c] << " (expected " << backRev[c] << ") | rev "
                        << ms.rev[c] << " formula " << rev[c] << " transit " << tr.rev[c] << " reverse-transit fwd "
                        << trBack.fwd[c] << " (expected " << backFwd[c] << ")\n";
                INFO(msg.str());
                CHECK(ok);
            }
        }
        std::printf("[stand-in densities] %-8s %ld collisions, %ld passes; worst relative differences: formula %.2e, "
                    "transit %.2e, reversed %.2e\n",
                    mc.name, collisions, passes, worstFormula, worstTransit, worstReverse);
        CHECK(failures == 0);
        CHECK(collisions > 300);
        CHECK(passes > 300);
        ++mi;
    }
}

// ---------------------------------------------------------------------------------------
// 7. Placement

TEST_CASE("heterogeneous medium: densityAt and sigmaSAt follow the placement", "[density]") {
    const int lo[3] = {-3, -2, -1}, hi[3] = {6, 5, 4};
    auto field = [](double i, double j, double k) { return 1 + 0.1 * i + 0.2 * j + 0.05 * k; };  // ≥ 0.25 on the box
    auto grid = buildGrid(lo, hi, [&](int i, int j, int k) { return float(field(i, j, k)); });
    // indexToWorld: scale 0.5 then translate (1, 0, 0). Node: rotate by θ about z, then
    // translate (2, −1, 3). World point of index p: node(indexToWorld(p)), written out here.
    const double theta = 0.6;
    Mat4 indexToWorld;
    indexToWorld(0, 0) = indexToWorld(1, 1) = indexToWorld(2, 2) = 0.5;
    indexToWorld(0, 3) = 1;
    const double nt[3] = {2, -1, 3}, nq[4] = {0, 0, std::sin(theta / 2), std::cos(theta / 2)}, ns[3] = {1, 1, 1};
    const Mat4 node = Mat4::fromTRS(nt, nq, ns);
    auto viaIndexToWorld = [&](Vec3 p) { return Vec3(0.5f * p.x + 1, 0.5f * p.y, 0.5f * p.z); };
    auto viaNode = [&](Vec3 a) {
        const double c = std::cos(theta), s = std::sin(theta);
        return Vec3(float(c * a.x - s * a.y + 2), float(s * a.x + c * a.y - 1), float(a.z + 3));
    };

    const float scale = 2.0f;
    Medium placed, unplaced;
    for (Medium* m : {&placed, &unplaced}) {
        m->sigmaS = Spectrum(0.3f, 0.6f, 0.9f);
        m->sigmaA = Spectrum(0.1f);
        m->density.grid = grid;
        m->density.indexToWorld = indexToWorld;
        m->density.scale = scale;
    }
    placed.density.place(node);
    unplaced.density.place(Mat4());

    Rng rng(71, 8);
    long moved = 0;
    const int N = 2000;
    for (int n = 0; n < N; ++n) {
        Vec3 p;
        for (int ax = 0; ax < 3; ++ax) p[ax] = float(lo[ax] + (hi[ax] - lo[ax]) * rng.next1D());
        const double want = scale * field(p.x, p.y, p.z);
        const Vec3 a = viaIndexToWorld(p), w = viaNode(a);
        INFO("index (" << p.x << ", " << p.y << ", " << p.z << ")");
        REQUIRE(placed.densityAt(w) == Approx(want).epsilon(1e-5));
        REQUIRE(unplaced.densityAt(a) == Approx(want).epsilon(1e-5));
        const Spectrum ss = placed.sigmaSAt(w);
        for (int c = 0; c < 3; ++c) REQUIRE(ss[c] == Approx(placed.sigmaS[c] * want).epsilon(1e-5));
        if (std::fabs(placed.densityAt(a) - want) > 1e-3) ++moved;
    }
    // The node really moved the field (at the unplaced position the placed field differs).
    CHECK(moved > N * 9 / 10);
    // Far outside: no density; sigmaSAt is 0 there too. A homogeneous medium has density 1.
    CHECK(placed.densityAt(viaNode(viaIndexToWorld(Vec3(20, 0, 0)))) == 0.0f);
    CHECK(placed.densityAt(Vec3(1000, 1000, 1000)) == 0.0f);
    CHECK(isBlack(placed.sigmaSAt(Vec3(-1000, 0, 0))));
    Medium homogeneous;
    homogeneous.sigmaS = Spectrum(0.4f);
    CHECK(homogeneous.densityAt(Vec3(5, 5, 5)) == 1.0f);
    CHECK(homogeneous.sigmaSAt(Vec3(5, 5, 5)).x == 0.4f);
}
