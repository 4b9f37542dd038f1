#include "viewport.hpp"

#include "speculum/app/engine_settings.hpp"
#include "speculum/core.hpp"

#include <algorithm>
#include <fstream>
#include <cmath>
#include <limits>

namespace speculum::editor {

app::ModuleInfo editorModuleInfo() {
    app::ModuleInfo info;
    info.name = "editor";
    info.aovs = {{"pick", "G-buffer emissive.a: material flags | material index << 2 (the viewport's pick)"}};
    return info;
}

Viewport::Viewport(const gpu::Context& ctx, Document& document) : ctx_(ctx), doc_(document) {
    rebuild();
    revision_ = doc_.revision();
    doc_.takeTouched();
}

Viewport::~Viewport() {
    vkDeviceWaitIdle(ctx_.device());
}

void Viewport::rebuild() {
    vkDeviceWaitIdle(ctx_.device());
    // Reverse order of construction: each one holds a reference to the renderer.
    runner_.reset();
    chain_.reset();
    renderer_.reset();
    renderer_ = std::make_unique<render::Renderer>(ctx_, doc_.scene(),
                                                   fromSettings<render::RendererOptions>(doc_.settings()));
    chain_ = std::make_unique<chain::Chain>(ctx_, *renderer_, doc_.settings());
    runner_ = std::make_unique<app::FrameRunner>(ctx_, *renderer_, width_, height_);
    first_ = true;
    bakePending_ = true;
    builtWith_.clear();
    for (const SettingDesc& d : doc_.settings().table()) builtWith_[d.name] = doc_.settings().get(d.name);
}

void Viewport::sync() {
    if (doc_.revision() == revision_) return;
    revision_ = doc_.revision();
    uint32_t touched = doc_.takeTouched();
    // Materials and probes are uploaded at construction; so are the renderer's settings
    // (render.*) and the probes' bake settings. The other settings are read every frame.
    const uint32_t materials = Document::bit(Command::Touches::Materials);
    bool rebuildNeeded = touched & ~(Document::bit(Command::Touches::Settings) | materials);
    for (const SettingDesc& d : doc_.settings().table()) {
        double now = doc_.settings().get(d.name);
        auto it = builtWith_.find(d.name);
        bool constructionTime =
            d.name.rfind("render.", 0) == 0 || (d.name.rfind("probes.", 0) == 0 && d.name != "probes.debug_view");
        if (constructionTime && it != builtWith_.end() && it->second != now) rebuildNeeded = true;
    }
    if (rebuildNeeded) {
        rebuild();
    } else if (touched & materials) {
        // Materials alone: new factors for the renderer, the reflections module's per-material
        // table (built at its construction), and probes baked again from scratch (with their
        // bounces, as a fresh start bakes them) since they captured the old materials.
        vkDeviceWaitIdle(ctx_.device());
        renderer_->updateMaterialFactors();
        chain_.reset();
        chain_ = std::make_unique<chain::Chain>(ctx_, *renderer_, doc_.settings());
        bakePending_ = true;
        first_ = true;
    }
}

void Viewport::updateProbes(const probes::Probes::Progress& progress) {
    if (chain_->update(doc_.settings(), progress)) bakePending_ = false;
}

const Settings& Viewport::interactiveSettings() {
    if (interactiveOverlay_.is_null()) {
        const std::string file = std::string(SPECULUM_SOURCE_DIR) + "/assets/settings/low.json";
        std::ifstream in(file);
        nlohmann::json low = nlohmann::json::parse(in, nullptr, false);
        interactiveOverlay_ = nlohmann::json::object();
        if (low.is_object())
            for (const auto& [key, value] : low.items())
                // Per-frame settings only: the probes' bake settings would bake again.
                if (key.rfind("reflections.", 0) == 0 || key == "probes.planar_interval")
                    interactiveOverlay_[key] = value;
        // And no reflections of reflections while moving: the colour pyramid is then the lit
        // image, without reflections.reproject (3.5-6.8 ms of a 60-75 ms frame at 330x256 on
        // lavapipe; 14.0 -> 15.0 fps at half scale). A mirror seen in a mirror shows the probes'
        // picture until the camera stops and the full settings refine the frame.
        interactiveOverlay_["reflections.multi_bounce"] = false;
    }
    interactive_ = doc_.settings();
    interactive_->fromJson(interactiveOverlay_, "assets/settings/low.json");
    return *interactive_;
}

app::FrameResult Viewport::render(const FrameRequest& request, const app::PresentHook& present, VkSemaphore wait,
                                  VkSemaphore signal) {
    if (request.camera.width != width_ || request.camera.height != height_) {
        width_ = request.camera.width;
        height_ = request.camera.height;
        runner_->resize(width_, height_);
        steadyFrames_ = 0;
    }
    frame_.previousCamera = frame_.camera;
    frame_.camera = request.camera;
    if (first_ || request.cameraCut) frame_.previousCamera = frame_.camera;
    if (first_ || request.cameraCut || frame_.camera.viewProj != frame_.previousCamera.viewProj) steadyFrames_ = 0;
    first_ = false;
    ++steadyFrames_;

    std::vector<std::string> aovs;
    if (request.pick) aovs = {"depth", "normal", "pick"};
    // The inspector's AOVs come from the reflections module: none on frames it does not run.
    bool inspect = request.inspect && doc_.settings().getBool("reflections.enabled");
    if (!inspect) pixel_.valid = false;
    if (inspect)
        for (const char* a : {"method", "iterations", "roughness", "reflection"}) aovs.push_back(a);
    if (request.screenshot) aovs.push_back("color");
    app::LitHook inner = chain_->litHook(request.interactive ? interactiveSettings() : doc_.settings(), frame_);
    app::LitHook hook = inner;
    hook.modules.push_back(editorModuleInfo());
    hook.addPasses = [inner](FrameGraph& g, const render::GBuffer& gbuffer, TextureHandle lit, app::ModuleAovs& a) {
        if (std::find(a.requested.begin(), a.requested.end(), "pick") != a.requested.end())
            a.provided["pick"] = {gbuffer.emissive, 1, 3};
        return inner.addPasses ? inner.addPasses(g, gbuffer, lit, a) : lit;
    };
    app::FrameResult result = runner_->render(frame_, aovs, hook, present, wait, signal);
    if (request.pick) pick_ = resolvePick(result, *request.pick, frame_.camera);
    if (inspect) {
        glm::ivec2 p = glm::clamp(*request.inspect, glm::ivec2(0), glm::ivec2(int(width_) - 1, int(height_) - 1));
        auto at = [&](const char* name, int c) {
            const app::AovImage& img = result.aovs.at(name);
            return img.rgba[(size_t(p.y) * img.width + size_t(p.x)) * 4 + size_t(c)];
        };
        pixel_.valid = true;
        pixel_.method = {at("method", 0), at("method", 1), at("method", 2)};
        pixel_.iterations = at("iterations", 0);
        pixel_.roughness = at("roughness", 0);
        pixel_.reflection = {at("reflection", 0), at("reflection", 1), at("reflection", 2)};
    }
    return result;
}

namespace {

float pointTriangleDistance2(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    // Ericson, Real-Time Collision Detection 5.1.5: the closest point by Voronoi regions.
    glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    auto d2of = [&](glm::vec3 q) { return glm::dot(p - q, p - q); };
    if (d1 <= 0 && d2 <= 0) return d2of(a);
    glm::vec3 bp = p - b;
    float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return d2of(b);
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return d2of(a + ab * (d1 / (d1 - d3)));
    glm::vec3 cp = p - c;
    float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return d2of(c);
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return d2of(a + ac * (d2 / (d2 - d6)));
    float va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return d2of(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    float denom = 1.0f / (va + vb + vc);
    return d2of(a + ab * (vb * denom) + ac * (vc * denom));
}

}  // namespace

Pick Viewport::resolvePick(const app::FrameResult& frame, glm::ivec2 pixel, const render::CameraState& camera) const {
    Pick pick;
    const app::AovImage& depth = frame.aovs.at("depth");
    pixel = glm::clamp(pixel, glm::ivec2(0), glm::ivec2(int(depth.width) - 1, int(depth.height) - 1));
    size_t at = (size_t(pixel.y) * depth.width + size_t(pixel.x)) * 4;
    float z = depth.rgba[at];
    if (!(z > 0.0f)) return pick;  // reversed-Z: 0 is the sky
    double ndcX = (pixel.x + 0.5) / camera.width * 2.0 - 1.0;
    double ndcY = (pixel.y + 0.5) / camera.height * 2.0 - 1.0;
    glm::dvec4 w = glm::dmat4(camera.invViewProj) * glm::dvec4(ndcX, ndcY, double(z), 1.0);
    pick.position = glm::vec3(glm::dvec3(w) / w.w);
    const app::AovImage& normal = frame.aovs.at("normal");
    glm::vec3 n(normal.rgba[at], normal.rgba[at + 1], normal.rgba[at + 2]);
    pick.normal = glm::length(n) > 1e-6f ? glm::normalize(n) : glm::vec3(0, 1, 0);
    uint32_t bits = uint32_t(std::lround(frame.aovs.at("pick").rgba[at]));
    pick.material = int(bits >> render::kMaterialIndexShift);
    pick.hit = true;
    // The G-buffer gives the surface point and its material; the node is the instance of that
    // material whose triangles pass nearest that point (exact up to coincident surfaces).
    const Scene& s = doc_.scene();
    float best = std::numeric_limits<float>::max();
    for (const Instance& inst : s.instances) {
        const Mesh& mesh = s.meshes[size_t(inst.mesh)];
        for (const Primitive& prim : mesh.primitives) {
            int mat = prim.material >= 0 ? prim.material : int(s.materials.size());
            if (mat != pick.material) continue;
            glm::vec3 local = glm::vec3(glm::inverse(inst.world) * glm::vec4(pick.position, 1.0f));
            glm::vec3 lo = prim.boundsMin - 1e-2f, hi = prim.boundsMax + 1e-2f;
            if (glm::any(glm::lessThan(local, lo)) || glm::any(glm::greaterThan(local, hi))) continue;
            for (size_t i = 0; i + 2 < prim.indices.size(); i += 3) {
                auto v = [&](size_t k) {
                    return glm::vec3(inst.world * glm::vec4(prim.vertices[prim.indices[i + k]].position, 1.0f));
                };
                float d = pointTriangleDistance2(pick.position, v(0), v(1), v(2));
                if (d < best) {
                    best = d;
                    pick.node = inst.node;
                }
            }
        }
    }
    return pick;
}

std::string Viewport::graphJson() const {
    return runner_->graphJson().dump();
}

}  // namespace speculum::editor
