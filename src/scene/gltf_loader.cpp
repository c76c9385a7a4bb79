// glTF loader: the entry point. Reads the file, checks the required extensions, then walks the
// default scene's node hierarchy depth first and flattens meshes, the camera and lights into
// world space.
#include "brume/scene/gltf_loader.h"

#include <algorithm>
#include <cmath>

#include "brume/scene/gltf_detail.h"

namespace brume {

namespace {

using gltf::at;
using gltf::checkIndex;
using gltf::num;
using gltf::Source;

constexpr const char* kSupportedRequiredExtensions[] = {
    "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior",
    "BRUME_media"};

void checkRequiredExtensions(const Source& src, const tinygltf::Model& model) {
    for (size_t i = 0; i < model.extensionsRequired.size(); ++i) {
        const std::string& name = model.extensionsRequired[i];
        bool supported = false;
        for (const char* s : kSupportedRequiredExtensions) supported = supported || name == s;
        if (!supported) src.fail(at("extensionsRequired", i), "extension '" + name + "' is not supported");
    }
}

void checkNumbers(const Source& src, const std::vector<double>& v, size_t n, const std::string& field) {
    if (v.size() != n) src.fail(field, "expected " + std::to_string(n) + " numbers, got " + std::to_string(v.size()));
    for (double x : v)
        if (!std::isfinite(x)) src.fail(field, "non-finite value " + num(x));
}

// The node's transform relative to its parent: matrix, or translation · rotation · scale.
Mat4 localTransform(const Source& src, const tinygltf::Node& node, const std::string& field) {
    if (!node.matrix.empty()) {
        checkNumbers(src, node.matrix, 16, field + ".matrix");
        Mat4 m;
        for (size_t k = 0; k < 16; ++k) m.m[k] = node.matrix[k];
        return m;
    }
    double t[3] = {0, 0, 0}, r[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
    if (!node.translation.empty()) {
        checkNumbers(src, node.translation, 3, field + ".translation");
        std::copy(node.translation.begin(), node.translation.end(), t);
    }
    if (!node.rotation.empty()) {
        checkNumbers(src, node.rotation, 4, field + ".rotation");
        double len = std::sqrt(node.rotation[0] * node.rotation[0] + node.rotation[1] * node.rotation[1] +
                               node.rotation[2] * node.rotation[2] + node.rotation[3] * node.rotation[3]);
        if (!(len > 0)) src.fail(field + ".rotation", "zero quaternion");
        for (size_t k = 0; k < 4; ++k) r[k] = node.rotation[k] / len;
    }
    if (!node.scale.empty()) {
        checkNumbers(src, node.scale, 3, field + ".scale");
        std::copy(node.scale.begin(), node.scale.end(), s);
    }
    return Mat4::fromTRS(t, r, s);
}

Camera makeCamera(const Source& src, const tinygltf::PerspectiveCamera& p, const Mat4& world,
                  const std::string& cameraField, const std::string& nodeField) {
    if (!(std::isfinite(p.yfov) && p.yfov > 0 && p.yfov < double(kPi)))
        src.fail(cameraField + ".perspective.yfov", "yfov " + num(p.yfov) + " is not in (0, pi)");
    if (!(std::isfinite(p.aspectRatio) && p.aspectRatio >= 0))
        src.fail(cameraField + ".perspective.aspectRatio", "aspectRatio " + num(p.aspectRatio) + " is not positive");
    Camera c;
    c.position = world.point(Vec3(0, 0, 0));
    Vec3 forward = world.vector(Vec3(0, 0, -1)), up = world.vector(Vec3(0, 1, 0));
    const float forwardLength = length(forward);
    if (!(forwardLength > 0 && std::isfinite(forwardLength) && isFinite(c.position)))
        src.fail(nodeField, "degenerate camera transform");
    forward /= forwardLength;
    up -= dot(up, forward) * forward;  // Gram–Schmidt: non-uniform scale may shear the axes
    const float upLength = length(up);
    if (!(upLength > 1e-6f * length(world.vector(Vec3(0, 1, 0))) && std::isfinite(upLength)))
        src.fail(nodeField, "degenerate camera transform: its up and forward axes are parallel");
    c.forward = forward;
    c.up = up / upLength;
    c.right = cross(c.forward, c.up);
    c.yfov = float(p.yfov);
    c.aspectRatio = float(p.aspectRatio);
    return c;
}

// Depth-first walk over one scene, with an explicit stack so deep hierarchies cannot overflow
// the call stack, and a cycle check along the current path.
class SceneWalker {
public:
    SceneWalker(const Source& src, const tinygltf::Model& model, SceneDescription& desc)
        : src_(src), model_(model), desc_(desc), onPath_(model.nodes.size(), 0) {}

    void walk(const tinygltf::Scene& scene, const std::string& sceneField) {
        for (size_t r = 0; r < scene.nodes.size(); ++r) {
            int root = checkIndex(src_, scene.nodes[r], model_.nodes.size(), at(sceneField + ".nodes", r), "node");
            enter(root, localTransform(src_, model_.nodes[size_t(root)], at("nodes", size_t(root))));
            while (!stack_.empty()) {
                Frame& top = stack_.back();
                const std::vector<int>& children = model_.nodes[size_t(top.node)].children;
                if (top.next == children.size()) {
                    onPath_[size_t(top.node)] = 0;
                    stack_.pop_back();
                    continue;
                }
                const std::string field = at(at("nodes", size_t(top.node)) + ".children", top.next);
                int child = checkIndex(src_, children[top.next++], model_.nodes.size(), field, "node");
                if (onPath_[size_t(child)])
                    src_.fail(field, "cycle in the node hierarchy: " + pathTo(child));
                Mat4 world = top.world * localTransform(src_, model_.nodes[size_t(child)], at("nodes", size_t(child)));
                enter(child, world);
            }
        }
    }

    bool hasCamera() const { return hasCamera_; }
    const std::string& orthographicCamera() const { return orthographic_; }

private:
    struct Frame {
        int node;
        Mat4 world;
        size_t next;  // next child to visit
    };

    void enter(int index, const Mat4& world) {
        onPath_[size_t(index)] = 1;
        stack_.push_back(Frame{index, world, 0});
        visit(index, world);
    }

    std::string pathTo(int child) const {
        std::string path;
        for (const Frame& f : stack_) path += "node " + std::to_string(f.node) + " -> ";
        return path + "node " + std::to_string(child);
    }

    void visit(int index, const Mat4& world) {
        const tinygltf::Node& node = model_.nodes[size_t(index)];
        const std::string nf = at("nodes", size_t(index));
        if (node.mesh != -1) gltf::appendMesh(src_, model_, node.mesh, world, nf + ".mesh", desc_, fallback_);
        if (node.camera != -1) {
            int ci = checkIndex(src_, node.camera, model_.cameras.size(), nf + ".camera", "camera");
            const tinygltf::Camera& camera = model_.cameras[size_t(ci)];
            if (camera.type == "perspective") {
                if (!hasCamera_)
                    desc_.camera = makeCamera(src_, camera.perspective, world, at("cameras", size_t(ci)), nf);
                hasCamera_ = true;
            } else if (orthographic_.empty()) {
                orthographic_ = at("cameras", size_t(ci)) + ".type";
            }
        }
        auto light = node.extensions.find("KHR_lights_punctual");
        if (light != node.extensions.end()) {
            const std::string field = nf + ".extensions.KHR_lights_punctual.light";
            const tinygltf::Value* index = gltf::member(light->second, "light");
            if (!index) src_.fail(field, "missing");
            desc_.lights.push_back(gltf::makeLight(src_, model_, gltf::integer(src_, *index, field), world, field));
        }
    }

    const Source& src_;
    const tinygltf::Model& model_;
    SceneDescription& desc_;
    gltf::FallbackMaterials fallback_;
    std::vector<char> onPath_;
    std::vector<Frame> stack_;
    bool hasCamera_ = false;
    std::string orthographic_;  // the first orthographic camera met, for the error message
};

// "extensions": {"BRUME_render": {"width": W, "height": H, "spp": N, "maxDepth": D}}: every
// member optional (width and height together); the limits are the command line's.
RenderSettings parseRenderSettings(const Source& src, const tinygltf::Value& v) {
    const std::string base = "extensions.BRUME_render";
    if (!v.IsObject()) src.fail(base, "expected an object");
    RenderSettings r;
    auto read = [&](const char* key, int lo, int hi, int& out) {
        const tinygltf::Value* m = gltf::member(v, key);
        if (!m) return false;
        const std::string field = base + "." + key;
        int x = gltf::integer(src, *m, field);
        if (x < lo || x > hi) src.fail(field, std::to_string(x) + " is not in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        out = x;
        return true;
    };
    const bool w = read("width", 1, 16384, r.width), h = read("height", 1, 16384, r.height);
    if (w != h) src.fail(base, "width and height go together");
    if (w && int64_t(r.width) * r.height > (int64_t(1) << 27)) src.fail(base, "more than 2^27 pixels");
    read("spp", 1, 1 << 24, r.spp);
    read("maxDepth", -1, 1000000, r.maxDepth);
    return r;
}

}  // namespace

SceneDescription loadGltf(const std::string& path) {
    const Source src{path};
    const tinygltf::Model model = gltf::readModel(src);
    checkRequiredExtensions(src, model);

    SceneDescription desc;
    desc.path = path;
    desc.files.push_back(path);
    gltf::addReferencedFiles(src, model, desc.files);
    auto media = model.extensions.find("BRUME_media");
    if (media != model.extensions.end()) gltf::parseMedia(src, media->second, desc);
    auto render = model.extensions.find("BRUME_render");
    if (render != model.extensions.end()) desc.render = parseRenderSettings(src, render->second);
    gltf::loadMaterials(src, model, desc);

    SceneWalker walker(src, model, desc);
    const int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (model.defaultScene >= 0 || !model.scenes.empty()) {
        checkIndex(src, sceneIndex, model.scenes.size(), "scene", "scene");
        walker.walk(model.scenes[size_t(sceneIndex)], at("scenes", size_t(sceneIndex)));
    }
    if (!walker.hasCamera()) {
        if (!walker.orthographicCamera().empty())
            src.fail(walker.orthographicCamera(), "orthographic cameras are not supported; use a perspective camera");
        src.fail("cameras", "no perspective camera in scene " + std::to_string(sceneIndex));
    }
    return desc;
}

}  // namespace brume
