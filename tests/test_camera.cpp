// Tests of the pinhole camera's importance (camera_importance.h): projection of scene points
// to film positions (inverse of Camera::generateRay), the half-open film rectangle, the
// normalisation of We and pdfDir, a chi-square test of pdfDir against generateRay's
// directions, the light-tracing normalisation that the bidirectional integrator relies on
// (Monte Carlo with the Film's splat path), and clipping of rays to the view frustum.
// Seeds are fixed; chi-square tests at significance 0.01 (Bonferroni-corrected), Monte Carlo
// comparisons at 4 standard errors.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "brume/film/film.h"
#include "brume/scene/camera.h"
#include "brume/scene/camera_importance.h"
#include "brume/sampling/sampler.h"
#include "support/test_support.h"

using namespace brume;
using namespace brume::test;

namespace {

// A camera at `position` looking along `forward` with `upHint` roughly up; the basis is
// built in double and orthonormal, right = forward × up as the glTF loader makes it.
Camera makeCamera(Vec3 position, Vec3 forward, Vec3 upHint, float yfov) {
    auto dn = [](double x, double y, double z, double* o) {
        double l = std::sqrt(x * x + y * y + z * z);
        o[0] = x / l, o[1] = y / l, o[2] = z / l;
    };
    double f[3], r[3], u[3];
    dn(forward.x, forward.y, forward.z, f);
    // right = normalize(forward × upHint); up = right × forward.
    dn(f[1] * upHint.z - f[2] * upHint.y, f[2] * upHint.x - f[0] * upHint.z, f[0] * upHint.y - f[1] * upHint.x, r);
    dn(r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0], u);
    Camera c;
    c.position = position;
    c.forward = Vec3(float(f[0]), float(f[1]), float(f[2]));
    c.right = Vec3(float(r[0]), float(r[1]), float(r[2]));
    c.up = Vec3(float(u[0]), float(u[1]), float(u[2]));
    c.yfov = yfov;
    c.aspectRatio = 1.0f;  // deliberately unlike width/height: it must not be used
    return c;
}

struct CameraCase {
    const char* name;
    Camera cam;
    int width, height;
};

std::vector<CameraCase> cameraCases() {
    return {
        {"wide 640x360", makeCamera(Vec3(0.7f, -1.3f, 2.1f), Vec3(0.3f, -0.5f, -0.8f), Vec3(0.2f, 1.0f, 0.1f), 0.9f),
         640, 360},
        {"tall 300x500", makeCamera(Vec3(-2.0f, 0.5f, 1.0f), Vec3(-0.6f, 0.2f, 0.4f), Vec3(0.0f, 0.3f, 1.0f), 0.45f),
         300, 500},
        {"fisheye-ish 97x13", makeCamera(Vec3(1.5f, 2.5f, -0.5f), Vec3(0.1f, 0.9f, 0.3f), Vec3(1.0f, 0.0f, 0.2f), 2.2f),
         97, 13},
    };
}

// Film half-extents, computed like Camera::generateRay.
void filmTangents(const Camera& cam, int width, int height, double* tanX, double* tanY) {
    float ty = std::tan(0.5f * cam.yfov);
    float tx = ty * float(width) / float(height);
    *tanX = tx;
    *tanY = ty;
}

// Direction through the plane point (sx, sy) at distance 1 (not normalised), in double.
void planeDirection(const Camera& cam, double sx, double sy, double w[3]) {
    w[0] = cam.forward.x + cam.right.x * sx + cam.up.x * sy;
    w[1] = cam.forward.y + cam.right.y * sx + cam.up.y * sy;
    w[2] = cam.forward.z + cam.right.z * sx + cam.up.z * sy;
}

// Uniform in [lo, hi)³, drawing the coordinates in order.
Vec3 randomVec(Sampler& rng, float lo, float hi) {
    float x = lo + (hi - lo) * rng.next1D();
    float y = lo + (hi - lo) * rng.next1D();
    float z = lo + (hi - lo) * rng.next1D();
    return Vec3(x, y, z);
}

Vec3 toVec3(const double w[3]) { return Vec3(float(w[0]), float(w[1]), float(w[2])); }

double ddot(Vec3 a, Vec3 b) { return double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z; }

// Running sums of one Monte Carlo variable over a fixed number of samples (zeros included).
struct Sums {
    double s1 = 0, s2 = 0;
    void add(double y) {
        s1 += y;
        s2 += y * y;
    }
    double mean(long n) const { return s1 / double(n); }
    double standardError(long n) const {
        double m = mean(n);
        double var = std::max(0.0, (s2 / double(n) - m * m) * double(n) / double(n - 1));
        return std::sqrt(var / double(n));
    }
};

}  // namespace

// ---------------------------------------------------------------------------------------
// Projection

TEST_CASE("connectToCamera inverts generateRay", "[camera]") {
    Sampler rng(11, 0, 0);
    for (const CameraCase& c : cameraCases()) {
        INFO(c.name);
        double tanX, tanY;
        filmTangents(c.cam, c.width, c.height, &tanX, &tanY);
        const double area = 4 * tanX * tanY;
        double maxErr = 0, maxDistErr = 0, maxWiErr = 0, maxWeErr = 0;
        long rejected = 0;
        for (int i = 0; i < 20000; ++i) {
            // Stay 0.01 pixel inside the film: at the very edge the float rounding of the ray
            // may legitimately move the point across it.
            float fx = 0.01f + rng.next1D() * (float(c.width) - 0.02f);
            float fy = 0.01f + rng.next1D() * (float(c.height) - 0.02f);
            Ray ray = c.cam.generateRay(fx, fy, c.width, c.height);
            float k = 0.5f + 20.0f * rng.next1D();
            CameraConnection cc;
            if (!connectToCamera(c.cam, ray.at(k), c.width, c.height, &cc)) {
                ++rejected;
                continue;
            }
            maxErr = std::max({maxErr, std::abs(double(cc.fx) - fx), std::abs(double(cc.fy) - fy)});
            maxDistErr = std::max(maxDistErr, std::abs(double(cc.dist) - k) / k);
            maxWiErr = std::max({maxWiErr, std::abs(double(cc.wi.x) + ray.d.x), std::abs(double(cc.wi.y) + ray.d.y),
                                 std::abs(double(cc.wi.z) + ray.d.z)});
            // We from the definition, with cosθ from the film position (independent of the code).
            double sx = (2.0 * fx / c.width - 1.0) * tanX, sy = (1.0 - 2.0 * fy / c.height) * tanY;
            double cos2 = 1.0 / (1.0 + sx * sx + sy * sy);
            double We = 1.0 / (area * cos2 * cos2);
            maxWeErr = std::max(maxWeErr, std::abs(cc.We - We) / We);
            CHECK(cc.pdf == 1.0f);
        }
        std::printf("[camera] %-18s round trip: max |Δf| = %.2e px, |Δdist|/dist = %.1e, |Δwi| = %.1e, "
                    "|ΔWe|/We = %.1e\n",
                    c.name, maxErr, maxDistErr, maxWiErr, maxWeErr);
        CHECK(rejected == 0);
        CHECK(maxErr < 1e-3);
        CHECK(maxDistErr < 1e-5);
        CHECK(maxWiErr < 1e-5);
        CHECK(maxWeErr < 1e-4);
    }
}

TEST_CASE("connectToCamera rejects points behind the camera and off the film", "[camera]") {
    Sampler rng(12, 0, 0);
    for (const CameraCase& c : cameraCases()) {
        INFO(c.name);
        const Camera& cam = c.cam;
        const float W = float(c.width), H = float(c.height);
        CameraConnection cc;
        CHECK_FALSE(connectToCamera(cam, cam.position, c.width, c.height, &cc));
        long wrong = 0;
        for (int i = 0; i < 20000; ++i) {
            // Behind the camera, or in its plane: any sideways offset.
            float back = (i % 10 == 0) ? 0.0f : 0.01f + 10.0f * rng.next1D();
            float a = 20.0f * rng.next1D() - 10.0f;
            float b = 20.0f * rng.next1D() - 10.0f;
            Vec3 side = cam.right * a + cam.up * b;
            if (connectToCamera(cam, cam.position - cam.forward * back + side, c.width, c.height, &cc)) ++wrong;
            // In front but off the film by at least 0.05 pixel (generateRay's formula extends
            // linearly beyond the film).
            float fx, fy;
            switch (i % 4) {
                case 0: fx = -0.05f - rng.next1D() * W; fy = rng.next1D() * H; break;
                case 1: fx = W + 0.05f + rng.next1D() * W; fy = rng.next1D() * H; break;
                case 2: fx = rng.next1D() * W; fy = -0.05f - rng.next1D() * H; break;
                default: fx = rng.next1D() * W; fy = H + 0.05f + rng.next1D() * H; break;
            }
            Ray ray = cam.generateRay(fx, fy, c.width, c.height);
            Vec3 p = ray.at(0.5f + 20.0f * rng.next1D());
            if (connectToCamera(cam, p, c.width, c.height, &cc)) ++wrong;
            if (cameraImportance(cam, ray.d, c.width, c.height) != 0.0f) ++wrong;
            if (cameraPdfDir(cam, ray.d, c.width, c.height) != 0.0f) ++wrong;
            if (cameraImportance(cam, -cam.forward, c.width, c.height) != 0.0f) ++wrong;
        }
        CHECK(wrong == 0);
    }
}

TEST_CASE("the film is the half-open rectangle [0, width) x [0, height)", "[camera]") {
    SECTION("exact edges of an axis-aligned camera") {
        // Camera at the origin looking down −Z: the vector (±tanX, ±tanY, −1) projects exactly
        // onto the film's edges (no rounding in the projection).
        Camera cam;
        cam.yfov = 0.8f;
        const int W = 64, H = 48;
        const float tanY = std::tan(0.5f * cam.yfov);
        const float tanX = tanY * float(W) / float(H);
        struct Edge {
            Vec3 v;
            bool inside;
            float fx, fy;
        };
        const Edge edges[] = {
            {Vec3(-tanX, 0, -1), true, 0.0f, 0.5f * H},       // left edge: x = 0 belongs to the film
            {Vec3(tanX, 0, -1), false, float(W), 0.5f * H},   // right edge: x = width does not
            {Vec3(0, tanY, -1), true, 0.5f * W, 0.0f},        // top edge: y = 0 does
            {Vec3(0, -tanY, -1), false, 0.5f * W, float(H)},  // bottom edge: y = height does not
            {Vec3(-tanX, tanY, -1), true, 0.0f, 0.0f},        // top-left corner: pixel (0, 0)
            {Vec3(tanX, -tanY, -1), false, float(W), float(H)},
            {Vec3(-tanX, -tanY, -1), false, 0.0f, float(H)},
            {Vec3(tanX, tanY, -1), false, float(W), 0.0f},
        };
        for (const Edge& e : edges) {
            for (float scale : {1.0f, 0.25f, 8.0f}) {
                Vec3 v = e.v * scale;
                INFO("v = (" << v.x << ", " << v.y << ", " << v.z << ")");
                CameraConnection cc;
                bool ok = connectToCamera(cam, v, W, H, &cc);
                CHECK(ok == e.inside);
                CHECK((cameraImportance(cam, v, W, H) > 0) == e.inside);
                CHECK((cameraPdfDir(cam, v, W, H) > 0) == e.inside);
                if (ok) {
                    CHECK(cc.fx == e.fx);
                    CHECK(cc.fy == e.fy);
                    SplatList splats;
                    splats.splat(cc.fx, cc.fy, Spectrum(1.0f), W, H);
                    REQUIRE(splats.records().size() == 1);
                    CHECK(splats.records()[0].x == int(e.fx));
                    CHECK(splats.records()[0].y == int(e.fy));
                }
            }
        }
        // One float step inside the left/top edges stays inside; one step inside the right
        // edge lands on width − (a fraction of an ulp of width): the float film position
        // rounds to width, and the point is rejected, as SplatList::splat would reject it.
        CameraConnection cc;
        CHECK(connectToCamera(cam, Vec3(std::nextafter(-tanX, 0.0f), 0, -1), W, H, &cc));
        bool ok = connectToCamera(cam, Vec3(std::nextafter(tanX, 0.0f), 0, -1), W, H, &cc);
        CHECK((ok && cc.fx < float(W)) == ok);
    }

    SECTION("near the edges of a rotated camera: all the functions and the splat agree") {
        Sampler rng(13, 0, 0);
        for (const CameraCase& c : cameraCases()) {
            INFO(c.name);
            const Camera& cam = c.cam;
            const float W = float(c.width), H = float(c.height);
            long accepted = 0, rejected = 0, disagree = 0, splatLost = 0;
            for (int i = 0; i < 40000; ++i) {
                // Film positions within ±1e-4 pixel of an edge.
                float jitter = (rng.next1D() - 0.5f) * 2e-4f;
                float fx = rng.next1D() * W, fy = rng.next1D() * H;
                switch (i % 4) {
                    case 0: fx = jitter; break;
                    case 1: fx = W + jitter; break;
                    case 2: fy = jitter; break;
                    default: fy = H + jitter; break;
                }
                Ray ray = cam.generateRay(fx, fy, c.width, c.height);
                Vec3 p = ray.at(0.5f + 20.0f * rng.next1D());
                CameraConnection cc;
                bool ok = connectToCamera(cam, p, c.width, c.height, &cc);
                Vec3 v = p - cam.position;  // the same float vector connectToCamera projects
                bool okI = cameraImportance(cam, v, c.width, c.height) > 0;
                bool okP = cameraPdfDir(cam, v, c.width, c.height) > 0;
                if (ok != okI || ok != okP) ++disagree;
                if (ok) {
                    ++accepted;
                    if (!(cc.fx >= 0 && cc.fx < W && cc.fy >= 0 && cc.fy < H)) ++disagree;
                    SplatList splats;
                    splats.splat(cc.fx, cc.fy, Spectrum(1.0f), c.width, c.height);
                    if (splats.records().size() != 1) ++splatLost;
                    else if (splats.records()[0].x >= c.width || splats.records()[0].y >= c.height) ++splatLost;
                } else {
                    ++rejected;
                }
            }
            std::printf("[camera] %-18s edge band: %ld accepted, %ld rejected\n", c.name, accepted, rejected);
            CHECK(disagree == 0);
            CHECK(splatLost == 0);
            // Both outcomes occur (the band straddles the edges).
            CHECK(accepted > 1000);
            CHECK(rejected > 1000);
        }
    }
}

// ---------------------------------------------------------------------------------------
// Normalisation and density

TEST_CASE("We cos and pdfDir integrate to one over the film", "[camera]") {
    for (const CameraCase& c : cameraCases()) {
        INFO(c.name);
        const Camera& cam = c.cam;
        double tanX, tanY;
        filmTangents(cam, c.width, c.height, &tanX, &tanY);
        // Over the plane at distance 1: dω = cos³θ dx dy. The domain stops a relative 1e-7
        // short of the film edges, where the functions jump to 0 (a negligible loss).
        const double sh = 1.0 - 1e-7;
        auto integrand = [&](bool importance) {
            return [&, importance](double sx, double sy) {
                double w[3];
                planeDirection(cam, sx, sy, w);
                double cos = 1.0 / std::sqrt(1.0 + sx * sx + sy * sy);
                double cos3 = cos * cos * cos;
                if (importance) return double(cameraImportance(cam, toVec3(w), c.width, c.height)) * cos * cos3;
                return double(cameraPdfDir(cam, toVec3(w), c.width, c.height)) * cos3;
            };
        };
        takeIntegrationBudgetWarnings();
        double iWe = integrate2D(integrand(true), -tanX * sh, tanX * sh, -tanY * sh, tanY * sh, 1e-9, 1e-7, 8);
        double iPdf = integrate2D(integrand(false), -tanX * sh, tanX * sh, -tanY * sh, tanY * sh, 1e-9, 1e-7, 8);
        int warnings = takeIntegrationBudgetWarnings();
        std::printf("[camera] %-18s ∫ We cosθ dω = %.8f, ∫ pdfDir dω = %.8f (quadrature warnings %d)\n", c.name, iWe,
                    iPdf, warnings);
        CHECK(iWe == Approx(1.0).epsilon(1e-5));
        CHECK(iPdf == Approx(1.0).epsilon(1e-5));

        // Zero outside the film: a grid over 3× the film, skipping a band of 1e-4 around it.
        long nonzero = 0;
        for (int i = 0; i <= 60; ++i) {
            for (int j = 0; j <= 60; ++j) {
                double sx = (-3.0 + 6.0 * i / 60.0) * tanX, sy = (-3.0 + 6.0 * j / 60.0) * tanY;
                if (std::abs(sx) < tanX * (1 + 1e-4) && std::abs(sy) < tanY * (1 + 1e-4)) continue;
                double w[3];
                planeDirection(cam, sx, sy, w);
                if (cameraImportance(cam, toVec3(w), c.width, c.height) != 0) ++nonzero;
                if (cameraPdfDir(cam, toVec3(w), c.width, c.height) != 0) ++nonzero;
            }
        }
        CHECK(nonzero == 0);

        // We(w) cosθ = pdfDir(w) pointwise, for unit and non-unit w.
        Sampler rng(14, 0, 0);
        double maxRel = 0;
        for (int i = 0; i < 10000; ++i) {
            double sx = (2 * rng.next1D() - 1) * tanX * sh, sy = (2 * rng.next1D() - 1) * tanY * sh;
            double w[3];
            planeDirection(cam, sx, sy, w);
            double scale = 0.1 + 10 * rng.next1D();
            Vec3 v = toVec3(w) * float(scale);
            double cos = ddot(v, cam.forward) / std::sqrt(ddot(v, v));
            double We = cameraImportance(cam, v, c.width, c.height), pdf = cameraPdfDir(cam, v, c.width, c.height);
            REQUIRE(pdf > 0);
            maxRel = std::max(maxRel, std::abs(We * cos - pdf) / pdf);
        }
        CHECK(maxRel < 1e-5);
    }
}

TEST_CASE("pdfDir is the density of generateRay's directions (chi-square)", "[camera][chi2]") {
    const auto cases = cameraCases();
    const double alpha = 0.01 / double(cases.size());
    for (const CameraCase& c : cases) {
        INFO(c.name);
        const Camera& cam = c.cam;
        double tanX, tanY;
        filmTangents(cam, c.width, c.height, &tanX, &tanY);
        // Histogram in (cosθ, φ) about forward: cosθ from a little below the film corners' up
        // to 1 (one empty bin from −1), φ all round. The film's rectangular boundary cuts
        // through the bins, so the density's support is tested too.
        const double cosCorner = 1.0 / std::sqrt(1.0 + tanX * tanX + tanY * tanY);
        const double lo = cosCorner - 0.01 * (1.0 - cosCorner);
        std::vector<double> edges = uniformEdges(24, lo, 1.0);
        edges.insert(edges.begin(), -1.0);
        SphereHistogramOptions opt;
        opt.axis = cam.forward;
        opt.cosThetaEdges = edges;
        opt.seed = 15;
        auto sample = [&](Sample2 u) -> std::optional<Vec3> {
            return cam.generateRay(u.u * float(c.width), u.v * float(c.height), c.width, c.height).d;
        };
        auto pdf = [&](Vec3 w) { return double(cameraPdfDir(cam, w, c.width, c.height)); };
        HistogramResult r = sphereHistogramTest(sample, pdf, 25, 32, 1000000, opt);
        std::printf("[chi2] camera pdfDir %-18s chi2 = %9.2f  dof = %4d  p = %.4f  integral = %.7f  (quadrature "
                    "warnings %d)\n",
                    c.name, r.chi2.chi2, r.chi2.dof, r.chi2.pValue, r.pdfIntegral, r.integrationWarnings);
        INFO(r.chi2.table);
        CHECK(r.invalid == 0);
        CHECK(r.outside == 0);
        CHECK(r.chi2.pValue > alpha);
        CHECK(r.pdfIntegral == Approx(1.0).epsilon(1e-3));
    }
}

// ---------------------------------------------------------------------------------------
// Light tracing: the constant factors of the splat rule

namespace {

// An emitting square facing the camera, tilted against the view direction, large enough to
// cover the whole view frustum (checked), so every film position sees it.
struct EmitterSetup {
    Camera cam;
    int width = 48, height = 32;
    int block = 8;  // pixel blocks of block × block pixels
    Vec3 center, n, s, t;
    double half = 0;  // half side of the square
    double area() const { return 4 * half * half; }

    EmitterSetup() {
        cam = makeCamera(Vec3(0.4f, -0.3f, 1.2f), Vec3(0.2f, -0.3f, -0.9f), Vec3(0.1f, 1.0f, 0.0f), 0.9f);
        center = cam.position + cam.forward * 4.0f;
        n = normalize(-cam.forward + cam.right * 0.3f - cam.up * 0.2f);  // faces the camera
        s = normalize(cross(n, cam.up));
        t = cross(n, s);
        // Corners of the frustum's footprint on the plane: the square must hold them.
        for (float fy : {0.0f, float(height)}) {
            for (float fx : {0.0f, float(width)}) {
                Ray r = cam.generateRay(fx, fy, width, height);
                std::optional<Vec3> hit = intersect(r.o, r.d);
                REQUIRE(hit);
                half = std::max({half, std::abs(ddot(*hit - center, s)), std::abs(ddot(*hit - center, t))});
            }
        }
        half *= 1.05;
    }
    // Intersection with the emitter's plane (ahead of o).
    std::optional<Vec3> intersect(Vec3 o, Vec3 d) const {
        double dn = ddot(d, n);
        if (dn == 0) return std::nullopt;
        double tt = ddot(center - o, n) / dn;
        if (!(tt > 0)) return std::nullopt;
        return o + d * float(tt);
    }
    bool onSquare(Vec3 p) const { return std::abs(ddot(p - center, s)) <= half && std::abs(ddot(p - center, t)) <= half; }
    Vec3 samplePoint(Sample2 u) const {
        return center + s * float((2.0 * u.u - 1.0) * half) + t * float((2.0 * u.v - 1.0) * half);
    }
    int blocksX() const { return width / block; }
    int blocksY() const { return height / block; }
    int blockOf(float fx, float fy) const { return (int(fy) / block) * blocksX() + int(fx) / block; }
};

// The light-tracing contribution of an emitter point p sampled uniformly on the square
// (p_A = 1 / area), whose radiance towards the camera is Le:
//     C = Le / p_A · We(−wi) · cosθ_cam · cos_p / dist²,
// cosθ_cam = dot(−wi, forward), cos_p = dot(n, wi). The pixel estimate is N_pixels · mean(C over
// the samples landing in the pixel), i.e. with one light sample per pixel per pass, the Film's
// division by the pass count gives exactly the pixel value.
double contribution(const EmitterSetup& e, const CameraConnection& cc, double Le) {
    double cosCam = -ddot(cc.wi, e.cam.forward);
    double cosP = ddot(e.n, cc.wi);
    if (!(cosP > 0)) return 0.0;  // one-sided emitter
    return Le * e.area() * cc.We * cosCam * cosP / (double(cc.dist) * cc.dist);
}

}  // namespace

TEST_CASE("light tracing through connectToCamera reproduces a uniform emitter filling the view", "[camera]") {
    // Radiance L everywhere on the film ⇒ every pixel must converge to L. One light sample per
    // pixel per pass, splatted with value C through SplatList / Film (which divides by passes).
    EmitterSetup e;
    const double L = 1.7;
    const int W = e.width, H = e.height, nPix = W * H;
    const int passes = 600;
    const long n = long(nPix) * passes;
    const int nBlocks = e.blocksX() * e.blocksY();
    const double pixPerBlock = double(e.block * e.block);

    Film film(W, H);
    SplatList splats;
    std::vector<Sums> blockSums{size_t(nBlocks)};
    Sums all;
    Sampler rng(21, 0, 0);
    long landed = 0;
    for (int pass = 0; pass < passes; ++pass) {
        splats.clear();
        for (int i = 0; i < nPix; ++i) {
            Vec3 p = e.samplePoint(rng.next2D());
            CameraConnection cc;
            if (!connectToCamera(e.cam, p, W, H, &cc)) continue;
            double C = contribution(e, cc, L);
            splats.splat(cc.fx, cc.fy, Spectrum(float(C)), W, H);
            // Block mean = (N_pix / n_block) · mean over all samples of C·[lands in block].
            blockSums[size_t(e.blockOf(cc.fx, cc.fy))].add(nPix / pixPerBlock * C);
            all.add(C);  // mean over all pixels = N_pix · mean(C) / N_pix
            ++landed;
        }
        film.mergeSplats(splats);
        film.completePass();
    }
    REQUIRE(film.passes() == passes);
    std::printf("[camera] uniform emitter: %ld of %ld samples landed; all pixels: %.5f ± %.5f (L = %.3f)\n", landed,
                n, all.mean(n), all.standardError(n), L);
    CHECK(std::abs(zScore(all.mean(n), L, all.standardError(n))) < 4);
    double worstZ = 0;
    for (int b = 0; b < nBlocks; ++b) {
        INFO("block " << b);
        double mean = blockSums[size_t(b)].mean(n), se = blockSums[size_t(b)].standardError(n);
        double z = zScore(mean, L, se);
        worstZ = std::max(worstZ, std::abs(z));
        CHECK(std::abs(z) < 4);
        CHECK(se < 0.02 * L);  // the test has the power to see a wrong cosθ at the corners
        // The film's block average is the same estimate.
        int bx = b % e.blocksX(), by = b / e.blocksX();
        double filmSum = 0;
        for (int y = by * e.block; y < (by + 1) * e.block; ++y)
            for (int x = bx * e.block; x < (bx + 1) * e.block; ++x) filmSum += film.pixel(x, y).x;
        CHECK(filmSum / pixPerBlock == Approx(mean).epsilon(1e-5));
    }
    std::printf("[camera] uniform emitter: %d blocks of %dx%d pixels, worst |z| = %.2f\n", nBlocks, e.block, e.block,
                worstZ);
}

TEST_CASE("light tracing matches camera tracing for a textured, directional emitter", "[camera]") {
    // Radiance varying over the emitter and with direction: light tracing (splat rule) and
    // camera tracing (mean radiance over uniform positions in the pixel) must agree per block.
    EmitterSetup e;
    auto radiance = [&](Vec3 p, Vec3 towardsCamera) {
        double a = ddot(p - e.center, e.s), b = ddot(p - e.center, e.t);
        return (1.0 + 0.8 * std::sin(3.0 * a) * std::cos(2.0 * b)) * (0.6 + 0.4 * ddot(e.n, towardsCamera));
    };
    const int W = e.width, H = e.height, nPix = W * H;
    const int nBlocks = e.blocksX() * e.blocksY();
    const double pixPerBlock = double(e.block * e.block);

    const long n = 2000000;
    std::vector<Sums> light{size_t(nBlocks)};
    Sampler rng(22, 0, 0);
    for (long i = 0; i < n; ++i) {
        Vec3 p = e.samplePoint(rng.next2D());
        CameraConnection cc;
        if (!connectToCamera(e.cam, p, W, H, &cc)) continue;
        double C = contribution(e, cc, radiance(p, cc.wi));
        light[size_t(e.blockOf(cc.fx, cc.fy))].add(nPix / pixPerBlock * C);
    }

    const long m = 20000;  // camera samples per block
    double worstZ = 0;
    for (int b = 0; b < nBlocks; ++b) {
        int bx = b % e.blocksX(), by = b / e.blocksX();
        RunningStats cam;
        for (long k = 0; k < m; ++k) {
            Sample2 u = rng.next2D();
            float fx = float(bx * e.block) + u.u * float(e.block), fy = float(by * e.block) + u.v * float(e.block);
            Ray r = e.cam.generateRay(fx, fy, W, H);
            std::optional<Vec3> hit = e.intersect(r.o, r.d);
            REQUIRE(hit);
            REQUIRE(e.onSquare(*hit));
            cam.add(radiance(*hit, -r.d));
        }
        double lm = light[size_t(b)].mean(n), ls = light[size_t(b)].standardError(n);
        double z = (lm - cam.mean()) / std::sqrt(ls * ls + cam.standardError() * cam.standardError());
        worstZ = std::max(worstZ, std::abs(z));
        INFO("block " << b << ": light " << lm << " ± " << ls << ", camera " << cam.mean() << " ± "
                      << cam.standardError());
        CHECK(std::abs(z) < 4);
    }
    std::printf("[camera] textured emitter: %d blocks, worst |z| light vs camera tracing = %.2f\n", nBlocks, worstZ);
}

// ---------------------------------------------------------------------------------------
// Frustum clipping

namespace {

// Signed distances of p to the four frustum planes (positive inside), the smallest one,
// relative to the scale of the numbers involved; computed in double.
double frustumMargin(const Camera& cam, int width, int height, double p[3]) {
    double tanX, tanY;
    filmTangents(cam, width, height, &tanX, &tanY);
    double q[3] = {p[0] - cam.position.x, p[1] - cam.position.y, p[2] - cam.position.z};
    auto along = [&](Vec3 a) { return q[0] * a.x + q[1] * a.y + q[2] * a.z; };
    double x = along(cam.right), y = along(cam.up), z = along(cam.forward);
    double gx = std::min(tanX * z - x, tanX * z + x) / std::sqrt(tanX * tanX + 1);
    double gy = std::min(tanY * z - y, tanY * z + y) / std::sqrt(tanY * tanY + 1);
    return std::min(gx, gy);
}

}  // namespace

TEST_CASE("clipToFrustum keeps exactly the part of a ray that projects on the film", "[camera]") {
    Sampler rng(31, 0, 0);
    for (const CameraCase& c : cameraCases()) {
        INFO(c.name);
        const Camera& cam = c.cam;
        long nearEnd = 0, lostNearEnd = 0;
        long nonEmpty = 0, empty = 0, lost = 0, badEnd = 0, badInterior = 0, outsideInput = 0, insideSamples = 0;
        for (int i = 0; i < 4000; ++i) {
            // Origins around the camera (in front, behind, beside); directions either random or
            // aimed at a point in the view (jittered), scaled to non-unit length.
            Vec3 o = cam.position + randomVec(rng, -4, 4);
            Vec3 d;
            if (i % 3 == 0) {
                d = normalize(randomVec(rng, -1, 1));
            } else {
                float fx = rng.next1D() * float(c.width);
                float fy = rng.next1D() * float(c.height);
                Ray r = cam.generateRay(fx, fy, c.width, c.height);
                Vec3 target = r.at(0.5f + 10 * rng.next1D()) + randomVec(rng, -0.15f, 0.15f);
                d = normalize(target - o);
            }
            if (i % 5 == 0) o = cam.position;  // rays from the apex
            d = d * (0.25f + 3 * rng.next1D());
            const float in0 = (i % 2 == 0) ? 0.0f : -5 * rng.next1D(), in1 = in0 + 0.1f + 15 * rng.next1D();
            float t0 = in0, t1 = in1;
            bool ok = clipToFrustum(cam, c.width, c.height, o, d, &t0, &t1);
            if (ok) {
                ++nonEmpty;
                if (!(t0 >= in0 && t1 <= in1 && t0 < t1)) ++outsideInput;
            } else {
                ++empty;
                if (t0 != in0 || t1 != in1) ++outsideInput;  // left unchanged
            }
            // Every sampled point that projects onto the film is kept.
            for (int k = 0; k < 200; ++k) {
                float t = in0 + (in1 - in0) * rng.next1D();
                CameraConnection cc;
                if (connectToCamera(cam, o + d * t, c.width, c.height, &cc)) {
                    ++insideSamples;
                    if (!ok || t < t0 || t > t1) ++lost;
                }
            }
            if (!ok) continue;
            // The clipped interval holds only points in the frustum (up to the rounding margin),
            // and each end is the input's or lies on a frustum face (smallest plane distance ~0).
            double scale = length(o) + length(cam.position) + std::max(std::abs(in0), std::abs(in1)) * length(d);
            for (int k = 0; k < 20; ++k) {
                double tt = t0 + (t1 - t0) * rng.next1D();
                double p[3] = {o.x + d.x * tt, o.y + d.y * tt, o.z + d.z * tt};
                if (!(frustumMargin(cam, c.width, c.height, p) >= -1e-5 * scale)) ++badInterior;
            }
            for (float te : {t0, t1}) {
                if (te == in0 || te == in1) continue;
                // Float steps around a clipped end: where rounding decides, nothing that
                // connectToCamera accepts may fall outside.
                float tt = te;
                for (int k = 0; k < 64; ++k) tt = std::nextafter(tt, -kInfinity);
                for (int k = 0; k < 128; ++k, tt = std::nextafter(tt, kInfinity)) {
                    if (tt < in0 || tt > in1) continue;
                    CameraConnection cc;
                    ++nearEnd;
                    if (connectToCamera(cam, o + d * tt, c.width, c.height, &cc) && (tt < t0 || tt > t1)) ++lostNearEnd;
                }
                double p[3] = {o.x + d.x * double(te), o.y + d.y * double(te), o.z + d.z * double(te)};
                if (!(std::abs(frustumMargin(cam, c.width, c.height, p)) <= 1e-5 * scale)) ++badEnd;
            }
        }
        std::printf("[camera] %-18s clip: %ld non-empty, %ld empty, %ld samples on the film, %ld float steps "
                    "around the ends\n",
                    c.name, nonEmpty, empty, insideSamples, nearEnd);
        CHECK(lost == 0);
        CHECK(lostNearEnd == 0);
        CHECK(badInterior == 0);
        CHECK(badEnd == 0);
        CHECK(outsideInput == 0);
        CHECK(nonEmpty > 500);
        CHECK(empty > 500);
    }
}

TEST_CASE("clipToFrustum special cases", "[camera]") {
    const CameraCase c = cameraCases()[0];
    const Camera& cam = c.cam;
    const int W = c.width, H = c.height;
    float t0, t1;
    SECTION("along the view axis from behind the camera") {
        t0 = 0, t1 = 10;
        REQUIRE(clipToFrustum(cam, W, H, cam.position - cam.forward * 2.0f, cam.forward, &t0, &t1));
        CHECK(t0 == Approx(2.0).margin(1e-4));
        CHECK(t1 == 10.0f);
    }
    SECTION("unbounded ray inside the frustum") {
        t0 = -kInfinity, t1 = kInfinity;
        REQUIRE(clipToFrustum(cam, W, H, cam.position, cam.generateRay(100, 200, W, H).d, &t0, &t1));
        CHECK(t0 == Approx(0.0).margin(1e-5));
        CHECK(t1 == kInfinity);
    }
    SECTION("entirely behind the camera") {
        t0 = 0, t1 = 100;
        CHECK_FALSE(clipToFrustum(cam, W, H, cam.position - cam.forward, -cam.forward + cam.right * 0.1f, &t0, &t1));
        CHECK(t0 == 0.0f);
        CHECK(t1 == 100.0f);
    }
    SECTION("crossing the view: the ends are on the left and right faces") {
        // A ray parallel to right, 5 units ahead: inside for |x| ≤ 5·tanX.
        double tanX, tanY;
        filmTangents(cam, W, H, &tanX, &tanY);
        Vec3 o = cam.position + cam.forward * 5.0f - cam.right * 20.0f;
        t0 = 0, t1 = 100;
        REQUIRE(clipToFrustum(cam, W, H, o, cam.right, &t0, &t1));
        CHECK(t0 == Approx(20.0 - 5.0 * tanX).epsilon(1e-5));
        CHECK(t1 == Approx(20.0 + 5.0 * tanX).epsilon(1e-5));
    }
    SECTION("passing beside the frustum") {
        Vec3 o = cam.position + cam.forward * 5.0f + cam.up * 20.0f - cam.right * 20.0f;
        t0 = 0, t1 = 100;
        CHECK_FALSE(clipToFrustum(cam, W, H, o, cam.right, &t0, &t1));
    }
    SECTION("degenerate input") {
        t0 = 5, t1 = 1;
        CHECK_FALSE(clipToFrustum(cam, W, H, cam.position, cam.forward, &t0, &t1));
        t0 = std::nanf(""), t1 = 1;
        CHECK_FALSE(clipToFrustum(cam, W, H, cam.position, cam.forward, &t0, &t1));
    }
}
