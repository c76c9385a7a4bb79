// The renderable scene: a SceneDescription plus one Embree scene over all meshes, the light
// list (punctual lights, then one entry per emissive triangle) and the light-picking
// distribution (proportional to power).
#pragma once
#include <embree3/rtcore.h>

#include <memory>
#include <vector>

#include "brume/math/ray.h"
#include "brume/sampling/distribution1d.h"
#include "brume/scene/bsdf.h"
#include "brume/scene/light_selection.h"
#include "brume/scene/scene_description.h"
#include "brume/scene/volume_lights.h"

namespace brume {

// How light points on emissive triangles are sampled from a reference point
// (scene/light_sampling.h): uniformly by area (the light point first, as the seed talk does),
// or uniformly in the solid angle the triangle subtends, with distances sampled by that
// solid angle on medium segments (integrators/solid_angle_segment.h).
enum class EmitterSampling { Area, SolidAngle };

// Where a ray met a surface, with everything shading needs.
struct SurfaceHit {
    float t = kInfinity;
    Vec3 p;
    Vec3 ng;          // geometric normal, front (counter-clockwise) side, unit
    Vec3 ns;          // shading normal on the same side as ng, unit
    float u = 0, v = 0;  // texture coordinates
    int mesh = -1, triangle = -1;
    int sphereLight = -1;  // index into lights() when the ray hit a sphere light instead
    bool valid() const { return mesh >= 0 || sphereLight >= 0; }
};

// The media a point lies in: a small stack of bounded media (the innermost on top) and the
// ambient medium below them. Crossing a medium boundary toggles that medium in the stack,
// so boundaries work whichever way their triangles wind.
struct MediumStack {
    static constexpr int kMaxDepth = 6;
    int media[kMaxDepth];
    int count = 0;
    int ambient = -1;
    int current() const { return count > 0 ? media[count - 1] : ambient; }
    void toggle(int medium);
};

class Scene {
public:
    explicit Scene(SceneDescription desc);
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    const SceneDescription& desc() const { return desc_; }
    const Camera& camera() const { return desc_.camera; }
    const std::vector<Light>& lights() const { return lights_; }
    const Distribution1D& lightDistribution() const { return lightDistribution_; }
    // Picks by where a connection starts (light_selection.h); power's where that does not apply.
    const LightSelection& lightSelection() const { return lightSelection_; }
    const Medium* medium(int index) const { return index >= 0 ? &desc_.media[index] : nullptr; }
    int mediumIndex(const Medium* m) const { return m ? int(m - desc_.media.data()) : -1; }
    const Material& material(int mesh) const { return desc_.materials[desc_.meshes[mesh].material]; }
    const Mesh& mesh(int index) const { return desc_.meshes[index]; }
    bool hasMedia() const { return !desc_.media.empty(); }
    // True if some medium is bounded by a mesh (a point's media then depend on where it is).
    bool hasBoundedMedia() const { return hasBoundedMedia_; }
    // True if some mesh is an invisible medium boundary that rays pass through.
    bool hasInvisibleBoundaries() const { return hasInvisibleBoundaries_; }
    // True if some emitter is a transparent light surface (Material::transparent): walks
    // gather its emission where they cross it.
    bool hasTransparentEmitters() const { return hasTransparentEmitters_; }
    // The emitting material a ray crosses at `hit` if it is a transparent emitter, else null.
    const Material* transparentEmitter(const SurfaceHit& hit) const {
        if (!hasTransparentEmitters_ || hit.mesh < 0) return nullptr;
        const Material& m = material(hit.mesh);
        return m.transparent && m.isEmissive() ? &m : nullptr;
    }
    // Whether light leaving light `li` straight into the pinhole counts (Material::cameraVisible).
    bool cameraSees(int li) const {
        const Light& l = lights_[size_t(li)];
        return l.mesh < 0 || material(l.mesh).cameraVisible;
    }
    // Colour channels whose free-flight densities differ somewhere: 3 if some medium is
    // coloured (its extinction differs between channels), else 1 (the MIS over channels of
    // the bidirectional tracer then has one term, and costs nothing).
    int mediumChannels() const { return mediumChannels_; }
    // True if a path can hit an emitter: some light is an emissive triangle or a sphere.
    bool hasHittableLights() const { return hasHittableLights_; }
    // True if some medium emits (Medium::emission): camera walks gather it on every piece
    // they cross, so they cannot stop or pass a piece early where such a medium may be.
    bool hasEmissiveMedia() const { return hasEmissiveMedia_; }
    // The emissive media that next-event estimation samples (those with an emission grid).
    const VolumeLights& volumeLights() const { return volumeLights_; }
    bool hasDirectionalLights() const { return hasDirectionalLights_; }
    // True if some light is an emissive triangle.
    bool hasTriangleLights() const { return hasTriangleLights_; }
    Vec3 boundsCenter() const { return boundsCenter_; }
    float boundsRadius() const { return boundsRadius_; }
    EmitterSampling emitterSampling() const { return emitterSampling_; }
    void setEmitterSampling(EmitterSampling e) { emitterSampling_ = e; }

    // Closest hit along the ray within [0, ray.tmax): triangles and sphere lights.
    SurfaceHit intersect(const Ray& ray) const;
    // True if a triangle or a sphere light other than `ignoreLight` blocks [0, ray.tmax).
    bool occluded(const Ray& ray, int ignoreLight = -1) const;
    // Light index of an emissive triangle, or -1.
    int triangleLight(int mesh, int triangle) const;
    // The other half of a rectangle (Light::partner ≥ 0).
    const Light& partnerOf(const Light& l) const { return lights_[size_t(triangleLight(l.mesh, l.partner))]; }
    // Emitted radiance leaving a surface point towards direction w (unit, away from it).
    Spectrum emission(const SurfaceHit& hit, Vec3 w) const;
    // The BSDF at a point of mesh `mesh` (texture coordinates u, v; normals as in SurfaceHit),
    // its base colour texture applied.
    Bsdf surfaceBsdf(int mesh, float u, float v, Vec3 ng, Vec3 ns) const;

    // The media at point p, by counting crossings of each medium boundary (odd = inside).
    MediumStack mediaAt(Vec3 p) const;
    const MediumStack& cameraMedia() const { return cameraMedia_; }
    // The media around light `index` (for an emissive triangle, on its front side, or its
    // back side when `back`), where light subpaths start.
    MediumStack lightMedia(int index, bool back = false) const;

    RTCScene embreeScene() const { return rtcScene_; }

private:
    SceneDescription desc_;
    std::vector<Light> lights_;
    std::vector<int> firstTriangleLight_;
    std::vector<int> sphereLights_;  // indices of sphere lights, intersected analytically
    MediumStack cameraMedia_;
    bool hasBoundedMedia_ = false;
    std::vector<MediumStack> lightMedia_;  // per light: front side; then per light: back side
    bool hasInvisibleBoundaries_ = false;
    bool hasTransparentEmitters_ = false;
    int mediumChannels_ = 1;
    bool hasHittableLights_ = false;
    bool hasEmissiveMedia_ = false;
    bool hasDirectionalLights_ = false;
    bool hasTriangleLights_ = false;  // per mesh, -1 if not emissive
    Distribution1D lightDistribution_;
    LightSelection lightSelection_;
    VolumeLights volumeLights_;
    Vec3 boundsCenter_;
    float boundsRadius_ = 0;
    EmitterSampling emitterSampling_ = EmitterSampling::SolidAngle;
    RTCDevice device_ = nullptr;
    RTCScene rtcScene_ = nullptr;
};

}  // namespace brume
