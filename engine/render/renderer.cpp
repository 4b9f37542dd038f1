// Renderer construction: environment choice, scene upload, pipelines.
#include "renderer_impl.hpp"

#include "speculum/core.hpp"

namespace speculum::render {
namespace {

// Sky for scenes that name no environment map.
constexpr glm::vec3 kDefaultSky{0.5f, 0.6f, 0.8f};

// The glTF scene shown by default: "scene" when given, else the first.
const nlohmann::json* sceneExtras(const nlohmann::json& doc) {
    if (!doc.is_object() || !doc.contains("scenes") || !doc["scenes"].is_array() ||
        doc["scenes"].empty())
        return nullptr;
    size_t index = 0;
    if (doc.contains("scene") && doc["scene"].is_number_unsigned())
        index = doc["scene"].get<size_t>();
    if (index >= doc["scenes"].size()) return nullptr;
    const nlohmann::json& s = doc["scenes"][index];
    if (!s.is_object() || !s.contains("extras") || !s["extras"].is_object()) return nullptr;
    return &s["extras"];
}

std::unique_ptr<Environment> makeEnvironment(const gpu::Context& ctx, const Scene& scene,
                                             RendererOptions& options) {
    const nlohmann::json* extras = sceneExtras(scene.document);
    if (extras && extras->contains("exposure")) {
        const auto& e = (*extras)["exposure"];
        if (!e.is_number() || !std::isfinite(e.get<double>()) || e.get<double>() <= 0.0)
            throw inputError(scene.path.string(),
                             "scene extras 'exposure' must be a positive number");
        // The scene sets its exposure; the user's option adjusts it relative to that.
        options.exposure *= e.get<float>();
    }
    if (extras && extras->contains("environment")) {
        const auto& env = (*extras)["environment"];
        if (!env.is_string())
            throw inputError(scene.path.string(),
                             "scene extras 'environment' must be a path string");
        std::filesystem::path file = scene.path.parent_path() / env.get<std::string>();
        return std::make_unique<Environment>(ctx, file, options.environment);
    }
    return std::make_unique<Environment>(ctx, kDefaultSky, options.environment);
}

}  // namespace

Renderer::Impl::Impl(const gpu::Context& c, const Scene& s, const RendererOptions& o)
    : ctx(c), scene(s), options(o) {
    environment = makeEnvironment(ctx, scene, options);
    gpuScene = uploadScene(ctx, scene);
    shadow = fitShadow(scene, options.shadowMapSize);
    createGBufferPipelines();
    createShadowResources();
    createLightingResources();
    createTonemapPipeline();
}

Renderer::Renderer(const gpu::Context& ctx, const Scene& scene, const RendererOptions& options)
    : impl_(std::make_unique<Impl>(ctx, scene, options)) {}

Renderer::~Renderer() = default;

const std::vector<uint32_t>& Renderer::lightingConstants() const { return impl_->lightingSpecialization; }
const Environment& Renderer::environment() const {
    return *impl_->environment;
}
const Scene& Renderer::scene() const {
    return impl_->scene;
}
RendererOptions& Renderer::options() {
    return impl_->options;
}

void Renderer::setNodeVisible(int node, bool visible) {
    for (DrawItem& d : impl_->gpuScene.draws)
        if (d.node == node && d.hidden == visible) {
            d.hidden = !visible;
            impl_->shadowCasters += 1;  // the shadow map is drawn again (shadow.cpp)
        }
}

void Renderer::updateMaterialFactors() {
    const Scene& s = impl_->scene;
    std::vector<GpuMaterial>& gpu = impl_->gpuScene.materials;
    const uint32_t indexBits = ~((1u << kMaterialIndexShift) - 1u);
    for (size_t i = 0; i < s.materials.size() && i < gpu.size(); ++i) {
        const Material& m = s.materials[i];
        GpuMaterial& g = gpu[i];
        g.baseColor = m.baseColor;
        g.metallic = m.metallic;
        g.roughness = m.roughness;
        g.flags = (g.flags & indexBits) | (m.unlit ? kFlagUnlit : 0u) | (reflects(m) ? kFlagReflective : 0u);
    }
}

}  // namespace speculum::render
