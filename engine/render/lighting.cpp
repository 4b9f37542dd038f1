// render.lighting: a fullscreen fragment pass, one invocation per pixel (lighting.frag). Lights, the shadow
// matrix and the irradiance SH never change for a scene: lighting.frag takes the lights and SH as
// specialization constants, the shadow mask reads the shadow matrix from one buffer written at
// construction; per-frame data fits in push constants.
#include "renderer_impl.hpp"

#include "speculum/core.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <vector>

namespace speculum::render {
namespace {

constexpr uint32_t kMaxLights = 16;

// Mirrors of shaders/engine/lighting_common.glsl: GpuLight as lighting.frag unpacks it from its
// specialization constants, GpuSceneShadow the shadow mask's std140 uniform buffer.
struct GpuLight {
    glm::vec4 positionType;
    glm::vec4 directionRange;
    glm::vec4 radiance;
    glm::vec4 cone;
};
struct GpuSceneShadow {
    glm::mat4 shadowViewProj;
    glm::vec4 shadowParams;
    glm::vec4 shadowToLight;
};
struct StaticLighting {
    GpuSceneShadow shadow;
    std::array<glm::vec4, 9> sh;
    uint32_t count = 0, directional = 0;  // directional lights come first
    std::array<GpuLight, kMaxLights> lights;
};

struct LightingConstants {
    glm::mat4 invViewProj;
    glm::vec4 cameraPosition;  // w: specular cube max mip
    glm::uvec4 size;  // xy: output size (light counts are specialization constants)
};
static_assert(sizeof(LightingConstants) <= 128);

GpuLight toGpu(const Light& l, bool shadowed) {
    GpuLight g{};
    float type = l.type == LightType::Directional ? 0.0f : l.type == LightType::Point ? 1.0f : 2.0f;
    g.positionType = glm::vec4(l.position, type);
    glm::vec3 dir =
        glm::length(l.direction) > 0.0f ? glm::normalize(l.direction) : glm::vec3(0, 0, -1);
    g.directionRange = glm::vec4(dir, l.range);
    g.radiance = glm::vec4(l.color * l.intensity, shadowed ? 1.0f : 0.0f);
    // glTF's recommended spot falloff, as a scale and offset on cos(angle).
    float cosOuter = std::cos(l.outerConeAngle);
    float cosInner = std::cos(l.innerConeAngle);
    float scale = 1.0f / std::max(cosInner - cosOuter, 1e-3f);
    g.cone = glm::vec4(scale, -cosOuter * scale, 0.0f, 0.0f);
    return g;
}

StaticLighting buildStaticLighting(const Scene& scene, const ShadowSetup& shadow,
                                   const Environment& env, uint32_t shadowMapSize) {
    StaticLighting s{};
    s.shadow.shadowViewProj = shadow.viewProj;
    // Normal offset of 1.5 texels and a constant bias of one texel's world size in depth keep
    // lit planes free of acne under the mask's 2x2 filter.
    s.shadow.shadowParams = glm::vec4(float(shadowMapSize), shadow.depthTexel, 1.5f * shadow.worldTexel,
                               shadow.enabled ? 1.0f : 0.0f);
    s.shadow.shadowToLight = glm::vec4(shadow.toLight, 0.0f);
    s.sh = env.irradianceSH();
    bool shadowAssigned = false;
    uint32_t count = 0;
    for (const Light& l : scene.lights) {
        if (count == kMaxLights) {
            logWarning("render: the scene has " + std::to_string(scene.lights.size()) +
                       " lights; only the first " + std::to_string(kMaxLights) + " are used");
            break;
        }
        bool shadowed = shadow.enabled && !shadowAssigned && l.type == LightType::Directional;
        shadowAssigned |= shadowed;
        s.lights[count++] = toGpu(l, shadowed);
    }
    // Directional lights first, so that the shader runs one loop per kind without a branch on
    // the type (both sides of which a SIMD CPU driver would execute); the shadowed one (the
    // first directional) stays first.
    auto isDirectional = [](const GpuLight& g) { return g.positionType.w == 0.0f; };
    auto directional =
        std::stable_partition(s.lights.begin(), s.lights.begin() + count, isDirectional);
    s.count = count;
    s.directional = uint32_t(directional - s.lights.begin());
    return s;
}

// lighting.frag's specialization constants: the light counts (ids 0, 1), the irradiance SH
// rgb from id 2, light i's four vec4 from id 32 + 16 i (floats as their bits).
std::vector<uint32_t> specializationOf(const StaticLighting& s) {
    constexpr size_t kShId = 2, kLightsId = 32;
    std::vector<uint32_t> c(kLightsId + sizeof(s.lights) / sizeof(float), 0u);
    c[0] = s.directional;
    c[1] = s.count;
    for (size_t k = 0; k < s.sh.size(); ++k)
        for (int j = 0; j < 3; ++j) c[kShId + 3 * k + size_t(j)] = std::bit_cast<uint32_t>(s.sh[k][j]);
    static_assert(sizeof(GpuLight) == 16 * sizeof(float));
    std::memcpy(c.data() + kLightsId, s.lights.data(), sizeof(s.lights));
    return c;
}

}  // namespace

void Renderer::Impl::createLightingResources() {
    StaticLighting data = buildStaticLighting(scene, shadow, *environment, options.shadowMapSize);
    gpu::GraphicsPipelineDesc d = fullscreenPipelineDesc("engine/lighting.frag", kLinearFormat, "render.lighting");
    d.pushConstantBytes = sizeof(LightingConstants);
    lightingSpecialization = specializationOf(data);
    d.fragmentConstants = lightingSpecialization;
    lightingPipeline = gpu::createGraphicsPipeline(ctx, d);
    sceneShadow = gpu::uploadBuffer(ctx, std::as_bytes(std::span(&data.shadow, 1)),
                                    VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, "render.scene_shadow");
    nearestSampler =
        gpu::createSampler(ctx, VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, false);
}

void Renderer::Impl::recordLighting(PassContext& pass, const FrameInputs& frame, const GBuffer& g,
                                    TextureHandle out, const LightingOptions& lighting) const {
    VkCommandBuffer cmd = pass.cmd();
    VkExtent2D extent = pass.extent(out);
    VkSampler nearest = nearestSampler;
    VkImageView maskView = g.shadowMask.valid() ? pass.view(g.shadowMask) : dummyShadowMask.view();
    beginFullscreenRendering(cmd, extent, pass.view(out));
    lightingPipeline.bind(cmd);
    gpu::DescriptorWriter()
        .sampled("depthTex", pass.view(g.depth), nearest)
        .sampled("albedoTex", pass.view(g.albedo), nearest)
        .sampled("normalTex", pass.view(g.normal), nearest)
        .sampled("emissiveTex", pass.view(g.emissive), nearest)
        .sampled("shadowMask", maskView, nearest)
        .sampled("envSpecular", environment->specular().view(), environment->sampler())
        .sampled("envDFG", environment->dfg().view(), environment->sampler())
        .push(ctx, cmd, lightingPipeline);
    LightingConstants c{frame.camera.invViewProj,
                        glm::vec4(frame.camera.position, float(environment->mipCount() - 1)),
                        glm::uvec4(extent.width, extent.height,
                                   lighting.moduleSpecular ? 1u : 0u, frame.directSpecular ? 0u : 1u)};
    vkCmdPushConstants(cmd, lightingPipeline.layout(),
                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(c), &c);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
}

TextureHandle Renderer::addLightingPass(FrameGraph& graph, const FrameInputs& frame,
                                        const GBuffer& gbuffer, const LightingOptions& lighting) {
    struct LightingData {
        GBuffer g;
        TextureHandle linear;
    };
    Impl* impl = impl_.get();
    const auto& d = graph.addPass<LightingData>(
        "render.lighting", PassType::Raster,
        [&](PassBuilder& b, LightingData& data) {
            data.g = readSurfaceAttachments(b, gbuffer);
            if (gbuffer.shadowMask.valid())
                data.g.shadowMask = b.read(gbuffer.shadowMask, TextureUsage::Sampled);
            data.linear = b.write(b.create("render.linear", TextureDesc{.format = kLinearFormat}),
                                  TextureUsage::ColorAttachment);
        },
        [impl, frame, lighting](const LightingData& data, PassContext& ctx) {
            impl->recordLighting(ctx, frame, data.g, data.linear, lighting);
        });
    return d.linear;
}

}  // namespace speculum::render
