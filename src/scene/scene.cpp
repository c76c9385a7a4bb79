#include "brume/scene/scene.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "brume/scene/light_sampling.h"
#include "brume/scene/sphere_intersect.h"

namespace brume {

// Rectangles among the emissive triangles: consecutive triangles (2k, 2k + 1) of a mesh that
// share two vertices a, c (the diagonal), whose other vertices b, d satisfy a + c = b + d (a
// parallelogram: the diagonals bisect each other) and |a − c| = |b − d| (equal diagonals: a
// rectangle), facing the same way. Within a relative 1e-4 of the diagonal's length.
static void pairRectangles(const SceneDescription& desc, std::vector<Light>& lights, const std::vector<int>& firstLight) {
    for (size_t m = 0; m < desc.meshes.size(); ++m) {
        if (firstLight[m] < 0) continue;
        const Mesh& mesh = desc.meshes[m];
        for (int t = 0; t + 1 < mesh.triangleCount(); t += 2) {
            const uint32_t* i1 = &mesh.indices[3 * t];
            const uint32_t* i2 = &mesh.indices[3 * (t + 1)];
            // The vertex of each triangle that the other lacks.
            int lone1 = -1, lone2 = -1, shared = 0;
            for (int k = 0; k < 3; ++k) {
                const bool in2 = i1[k] == i2[0] || i1[k] == i2[1] || i1[k] == i2[2];
                const bool in1 = i2[k] == i1[0] || i2[k] == i1[1] || i2[k] == i1[2];
                shared += in2;
                if (!in2) lone1 = k;
                if (!in1) lone2 = k;
            }
            if (shared != 2 || lone1 < 0 || lone2 < 0) continue;
            const Vec3 b = mesh.positions[i1[lone1]], d = mesh.positions[i2[lone2]];
            const Vec3 a = mesh.positions[i1[(lone1 + 1) % 3]], c = mesh.positions[i1[(lone1 + 2) % 3]];
            const float diag = length(a - c), tol = 1e-4f * diag;
            if (!(diag > 0) || length((a + c) - (b + d)) > tol || std::abs(length(b - d) - diag) > tol) continue;
            const Vec3 n1 = cross(a - b, c - b);
            const Vec3 n2 = cross(mesh.positions[i2[1]] - mesh.positions[i2[0]], mesh.positions[i2[2]] - mesh.positions[i2[0]]);
            const Vec3 f1 = cross(mesh.positions[i1[1]] - mesh.positions[i1[0]], mesh.positions[i1[2]] - mesh.positions[i1[0]]);
            if (!(dot(f1, n2) > 0) || !(length(n1) > 0)) continue;
            // The corner b (the lower-numbered half's own vertex) and the edges from it.
            for (int k = 0; k < 2; ++k) {
                Light& l = lights[size_t(firstLight[m] + t + k)];
                l.partner = t + 1 - k;
                l.rectCorner = b;
                l.rectEdgeU = a - b;
                l.rectEdgeV = c - b;
            }
        }
    }
}


void MediumStack::toggle(int medium) {
    for (int i = 0; i < count; ++i)
        if (media[i] == medium) {  // leaving: remove it, keep the order of the rest
            for (int j = i; j + 1 < count; ++j) media[j] = media[j + 1];
            --count;
            return;
        }
    if (count < kMaxDepth) media[count++] = medium;  // entering
}

// Embree calls this from C code, so it must not throw; errors surface as missing hits.
static void embreeError(void*, RTCError code, const char* message) {
    std::fprintf(stderr, "brume: embree error %d: %s\n", int(code), message ? message : "");
}

Scene::Scene(SceneDescription desc) : desc_(std::move(desc)) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("cannot create an Embree device");
    rtcSetDeviceErrorFunction(device_, embreeError, nullptr);
    rtcScene_ = rtcNewScene(device_);
    // Robust mode: watertight edges, so closed medium boundaries and furnace cavities never leak.
    rtcSetSceneFlags(rtcScene_, RTC_SCENE_FLAG_ROBUST);

    Vec3 lo(kInfinity), hi(-kInfinity);
    auto grow = [&](Vec3 p) { lo = vmin(lo, p); hi = vmax(hi, p); };
    grow(desc_.camera.position);

    for (size_t m = 0; m < desc_.meshes.size(); ++m) {
        const Mesh& mesh = desc_.meshes[m];
        RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        // rtcSetNewGeometryBuffer pads the allocation as Embree's SSE loads require.
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), mesh.positions.size()));
        for (size_t i = 0; i < mesh.positions.size(); ++i) {
            v[3 * i] = mesh.positions[i].x;
            v[3 * i + 1] = mesh.positions[i].y;
            v[3 * i + 2] = mesh.positions[i].z;
            grow(mesh.positions[i]);
        }
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh.triangleCount()));
        std::copy(mesh.indices.begin(), mesh.indices.end(), idx);
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(rtcScene_, geom, unsigned(m));
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(rtcScene_);

    lights_ = desc_.lights;
    for (size_t i = 0; i < lights_.size(); ++i) {
        if (lights_[i].kind != LightKind::Directional) grow(lights_[i].position);
        if (lights_[i].kind == LightKind::Sphere) sphereLights_.push_back(int(i));
    }
    boundsCenter_ = (lo + hi) * 0.5f;
    boundsRadius_ = std::max(1e-3f, 0.5f * length(hi - lo));

    // Emissive triangles become lights of their own, after the punctual ones.
    firstTriangleLight_.assign(desc_.meshes.size(), -1);
    for (size_t m = 0; m < desc_.meshes.size(); ++m) {
        const Mesh& mesh = desc_.meshes[m];
        if (mesh.material < 0 || !desc_.materials[mesh.material].isEmissive()) continue;
        firstTriangleLight_[m] = int(lights_.size());
        for (int t = 0; t < mesh.triangleCount(); ++t) {
            Light l;
            l.kind = LightKind::Triangle;
            l.mesh = int(m);
            l.triangle = t;
            lights_.push_back(l);
        }
    }
    pairRectangles(desc_, lights_, firstTriangleLight_);
    // The emitter record (light.h): the triangle's shape, its material's sides.
    for (Light& l : lights_) {
        if (!l.isPlanar()) continue;
        const Mesh& mesh = desc_.meshes[size_t(l.mesh)];
        const uint32_t* idx = &mesh.indices[3 * size_t(l.triangle)];
        EmitterTriangle& t = l.shape;
        t.p0 = mesh.positions[idx[0]], t.p1 = mesh.positions[idx[1]], t.p2 = mesh.positions[idx[2]];
        const Vec3 c = t.edgeCross();
        const float len = length(c);
        t.area = 0.5f * len;
        t.n = len > 0 ? c / len : Vec3(0, 0, 1);
        l.doubleSided = desc_.materials[size_t(mesh.material)].doubleSided;
    }
    // The whole emitter's centre and area (a rectangle's two halves), in the order of the
    // halves' numbers: the same bits from either half.
    for (Light& l : lights_) {
        if (!l.isPlanar()) continue;
        const EmitterTriangle* halves[2] = {&l.shape, nullptr};
        if (l.partner >= 0) {
            halves[1] = &partnerOf(l).shape;
            if (l.partner < l.triangle) std::swap(halves[0], halves[1]);
        }
        Vec3 sum(0.0f);
        float total = 0;
        for (const EmitterTriangle* t : halves) {
            if (!t) continue;
            sum += (t->p0 + t->p1 + t->p2) * (t->area / 3.0f);
            total += t->area;
        }
        l.emitterCentre = total > 0 ? sum / total : sum;
        l.emitterArea = total;
    }
    std::vector<float> power(lights_.size());
    for (size_t i = 0; i < lights_.size(); ++i) power[i] = lights_[i].power = lightPower(*this, lights_[i]);
    lightDistribution_ = Distribution1D(power);
    lightSelection_ = LightSelection(lights_, lightDistribution_);
    for (const Light& l : lights_) {
        hasHittableLights_ |= l.kind == LightKind::Triangle || l.kind == LightKind::Sphere;
        hasDirectionalLights_ |= l.kind == LightKind::Directional;
        hasTriangleLights_ |= l.kind == LightKind::Triangle;
    }

    for (const Mesh& mesh : desc_.meshes)
        if (mesh.material >= 0 && desc_.materials[mesh.material].kind == MaterialKind::Invisible) {
            hasInvisibleBoundaries_ = true;
            hasTransparentEmitters_ |= desc_.materials[mesh.material].isEmissive();
        }
    for (const Medium& m : desc_.media) {
        if (!m.grey()) mediumChannels_ = 3;
        hasEmissiveMedia_ |= m.emissive();
    }
    volumeLights_ = VolumeLights(desc_.media);
    cameraMedia_ = mediaAt(desc_.camera.position);

    // Where light subpaths start. Without bounded media every light sits in the ambient one.
    for (const Mesh& mesh : desc_.meshes) hasBoundedMedia_ |= mesh.interiorMedium >= 0;
    if (hasBoundedMedia_) {
        lightMedia_.resize(2 * lights_.size());
        for (size_t i = 0; i < lights_.size(); ++i) {
            const Light& l = lights_[i];
            if (l.kind == LightKind::Directional) {
                // Its rays start on a disc outside the scene's bounds, where no bounded medium
                // reaches, whatever the position of the light's node.
                MediumStack outside;
                outside.ambient = desc_.ambientMedium;
                lightMedia_[i] = lightMedia_[lights_.size() + i] = outside;
                continue;
            }
            if (l.kind != LightKind::Triangle) {
                lightMedia_[i] = lightMedia_[lights_.size() + i] = mediaAt(l.position);
                continue;
            }
            const EmitterTriangle& t = l.shape;
            const Vec3 c = (t.p0 + t.p1 + t.p2) / 3.0f, n = t.n;
            float eps = rayEpsilon(c);
            lightMedia_[i] = mediaAt(c + n * eps);
            lightMedia_[lights_.size() + i] = mediaAt(c - n * eps);
        }
    }
}

Scene::~Scene() {
    if (rtcScene_) rtcReleaseScene(rtcScene_);
    if (device_) rtcReleaseDevice(device_);
}

// Field by field (loadFloat, math/vec3.h): callers have just written the ray float by float.
static RTCRayHit toEmbree(const Ray& ray) {
    RTCRayHit rh;
    rh.ray.org_x = loadFloat(ray.o.x);
    rh.ray.org_y = loadFloat(ray.o.y);
    rh.ray.org_z = loadFloat(ray.o.z);
    rh.ray.dir_x = loadFloat(ray.d.x);
    rh.ray.dir_y = loadFloat(ray.d.y);
    rh.ray.dir_z = loadFloat(ray.d.z);
    rh.ray.tnear = loadFloat(ray.tmin);
    rh.ray.tfar = loadFloat(ray.tmax);
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.time = 0.0f;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

SurfaceHit Scene::intersect(const Ray& ray) const {
    SurfaceHit hit;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh = toEmbree(ray);
    rtcIntersect1(rtcScene_, &context, &rh);

    float tClosest = ray.tmax;
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) tClosest = rh.ray.tfar;
    for (int li : sphereLights_) {
        float t;
        if (intersectSphere(ray.o, ray.d, lights_[li].position, lights_[li].radius, tClosest, &t, ray.tmin)) {
            tClosest = t;
            hit.sphereLight = li;
        }
    }
    if (hit.sphereLight >= 0) {
        hit.t = tClosest;
        hit.p = ray.at(tClosest);
        Vec3 n = hit.p - lights_[hit.sphereLight].position;
        float len = length(n);
        hit.ng = hit.ns = len > 0 ? n / len : -ray.d;
        return hit;
    }
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;

    const Mesh& mesh = desc_.meshes[rh.hit.geomID];
    int tri = int(rh.hit.primID);
    uint32_t i0 = mesh.indices[3 * tri], i1 = mesh.indices[3 * tri + 1], i2 = mesh.indices[3 * tri + 2];
    Vec3 p0 = mesh.positions[i0], p1 = mesh.positions[i1], p2 = mesh.positions[i2];
    float b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1.0f - b1 - b2;
    hit.t = rh.ray.tfar;
    hit.mesh = int(rh.hit.geomID);
    hit.triangle = tri;
    hit.p = p0 * b0 + p1 * b1 + p2 * b2;
    Vec3 ng = cross(p1 - p0, p2 - p0);  // counter-clockwise winding: front side
    float len = length(ng);
    hit.ng = len > 0 ? ng / len : -ray.d;
    hit.ns = hit.ng;
    if (!mesh.normals.empty()) {
        Vec3 ns = mesh.normals[i0] * b0 + mesh.normals[i1] * b1 + mesh.normals[i2] * b2;
        float lns = length(ns);
        if (lns > 0 && std::isfinite(lns)) {
            ns = ns / lns;
            hit.ns = dot(ns, hit.ng) < 0 ? -ns : ns;
        }
    }
    if (!mesh.uvs.empty()) {
        hit.u = mesh.uvs[2 * i0] * b0 + mesh.uvs[2 * i1] * b1 + mesh.uvs[2 * i2] * b2;
        hit.v = mesh.uvs[2 * i0 + 1] * b0 + mesh.uvs[2 * i1 + 1] * b1 + mesh.uvs[2 * i2 + 1] * b2;
    }
    return hit;
}

bool Scene::occluded(const Ray& ray, int ignoreLight) const {
    for (int li : sphereLights_) {
        float t;
        if (li != ignoreLight && intersectSphere(ray.o, ray.d, lights_[li].position, lights_[li].radius, ray.tmax, &t, ray.tmin))
            return true;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh = toEmbree(ray);
    rtcOccluded1(rtcScene_, &context, &rh.ray);
    return rh.ray.tfar < 0;  // Embree sets tfar = −∞ on a hit
}

int Scene::triangleLight(int mesh, int triangle) const {
    int first = firstTriangleLight_[mesh];
    return first < 0 ? -1 : first + triangle;
}

Spectrum Scene::emission(const SurfaceHit& hit, Vec3 w) const {
    if (hit.sphereLight >= 0) {
        const Light& l = lights_[hit.sphereLight];
        return dot(hit.ng, w) > 0 ? l.intensity / (kPi * l.radius * l.radius) : Spectrum(0.0f);
    }
    const Material& m = material(hit.mesh);
    if (!m.isEmissive()) return Spectrum(0.0f);
    if (!m.doubleSided && dot(hit.ng, w) <= 0) return Spectrum(0.0f);
    Spectrum L = m.emission;
    if (m.emissiveTexture >= 0) L *= desc_.textures[m.emissiveTexture].lookup(hit.u, hit.v);
    return L;
}

Bsdf Scene::surfaceBsdf(int mesh, float u, float v, Vec3 ng, Vec3 ns) const {
    const Material& m = material(mesh);
    Spectrum base = m.baseColor;
    if (m.baseColorTexture >= 0) base *= desc_.textures[m.baseColorTexture].lookup(u, v);
    return Bsdf(m, base, ng, ns);
}

MediumStack Scene::lightMedia(int index, bool back) const {
    if (!hasBoundedMedia_) {
        MediumStack stack;
        stack.ambient = desc_.ambientMedium;
        return stack;
    }
    return lightMedia_[size_t(index) + (back ? lights_.size() : 0)];
}

MediumStack Scene::mediaAt(Vec3 p) const {
    MediumStack stack;
    stack.ambient = desc_.ambientMedium;
    // Walk a ray from p to infinity; a boundary crossed an odd number of times encloses p.
    // The boundary met first is the innermost, so media are pushed farthest-first.
    struct Crossing { int mesh; int count; float first; };
    std::vector<Crossing> crossings;
    Ray ray{p, normalize(Vec3(0.3141f, 0.8660f, 0.3872f)), kInfinity};
    float tBase = 0;
    for (int guard = 0; guard < 100000; ++guard) {
        SurfaceHit hit = intersect(ray);
        if (!hit.valid()) break;
        tBase += hit.t;
        if (hit.mesh >= 0 && desc_.meshes[hit.mesh].interiorMedium >= 0) {
            auto it = std::find_if(crossings.begin(), crossings.end(), [&](const Crossing& c) { return c.mesh == hit.mesh; });
            if (it == crossings.end()) crossings.push_back({hit.mesh, 1, tBase});
            else ++it->count;
        }
        ray.o = hit.p + ray.d * rayEpsilon(hit.p);
        tBase += rayEpsilon(hit.p);
    }
    std::sort(crossings.begin(), crossings.end(), [](const Crossing& a, const Crossing& b) { return a.first > b.first; });
    for (const Crossing& c : crossings)
        if (c.count % 2 == 1) stack.toggle(desc_.meshes[c.mesh].interiorMedium);
    return stack;
}

}  // namespace brume
