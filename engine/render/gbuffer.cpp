// render.shadow and render.gbuffer.
//
// Shadow map: orthographic projection fitted to the scene's bounding sphere, looking along the
// first directional light, reversed-Z like the main view (1 nearest the light, cleared to 0,
// GREATER_OR_EQUAL), D32. Bias: a slope-scaled raster bias away from the light plus a
// normal offset and constant bias at lookup time (lighting.comp).
//
// Alpha modes (MASK, BLEND) are ignored: every surface is opaque. Only TEXCOORD_0 is used.
#include "renderer_impl.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>

namespace speculum::render {
namespace {

// gpu::createGraphicsPipeline declares counter-clockwise front faces, as glTF does, so the
// pipeline's front is glTF's front (a mirrored transform swaps them per draw below).
constexpr bool kPipelineFrontIsGltfBack = false;
constexpr VkCullModeFlags kCullGltfBack =
    kPipelineFrontIsGltfBack ? VK_CULL_MODE_FRONT_BIT : VK_CULL_MODE_BACK_BIT;
constexpr VkCullModeFlags kCullGltfFront =
    kPipelineFrontIsGltfBack ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_FRONT_BIT;

// gpu::createGraphicsPipeline declares push constants for both stages.
constexpr VkShaderStageFlags kGraphicsPushStages =
    VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

constexpr uint32_t kDrawDoubleSided = 1;
constexpr uint32_t kDrawInvertFacing = 2;

struct FrameConstants {
    glm::mat4 viewProj;
    glm::mat4 prevViewProj;
};

struct DrawConstants {
    glm::mat4 model;
    glm::vec4 baseColor;
    glm::vec4 emissive;  // w: material flags
    glm::vec4 params;    // metallic, roughness, normal scale, draw flags
};
static_assert(sizeof(DrawConstants) <= 128, "push constants must fit lavapipe's 128 bytes");

const std::vector<gpu::Binding> kGBufferBindings = {
    {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_SHADER_STAGE_VERTEX_BIT},
    {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT},
    {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT},
    {3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT},
    {4, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_FRAGMENT_BIT},
};

// Which of the three G-buffer pipelines a draw uses.
enum class CullKind : uint8_t { Back, Front, None };

CullKind cullKind(const DrawItem& d, const GpuMaterial& m) {
    if (m.doubleSided) return CullKind::None;
    return d.mirrored ? CullKind::Front : CullKind::Back;
}

void beginRendering(VkCommandBuffer cmd, VkExtent2D extent, const std::vector<VkImageView>& colors,
                    VkImageView depth) {
    std::vector<VkRenderingAttachmentInfo> color(colors.size());
    for (size_t i = 0; i < colors.size(); ++i) {
        color[i] = {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        color[i].imageView = colors[i];
        color[i].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        color[i].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        color[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    }
    VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depthInfo.imageView = depth;
    depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depthInfo.clearValue.depthStencil = {0.0f, 0};  // reversed-Z: 0 is infinitely far
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, extent};
    info.layerCount = 1;
    info.colorAttachmentCount = uint32_t(color.size());
    info.pColorAttachments = color.data();
    info.pDepthAttachment = &depthInfo;
    vkCmdBeginRendering(cmd, &info);
    VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
    VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
}

// The constants live in one persistent buffer, so the update is ordered against the previous
// frame's reads and this frame's vertex shaders by hand (the graph does not track it).
void updateFrameConstants(VkCommandBuffer cmd, VkBuffer buffer, const FrameConstants& constants) {
    VkBufferMemoryBarrier2 b{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
    b.srcStageMask = VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT;
    b.srcAccessMask = VK_ACCESS_2_UNIFORM_READ_BIT;
    b.dstStageMask = VK_PIPELINE_STAGE_2_TRANSFER_BIT;
    b.dstAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.buffer = buffer;
    b.size = VK_WHOLE_SIZE;
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.bufferMemoryBarrierCount = 1;
    dep.pBufferMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &dep);
    vkCmdUpdateBuffer(cmd, buffer, 0, sizeof(constants), &constants);
    std::swap(b.srcStageMask, b.dstStageMask);
    std::swap(b.srcAccessMask, b.dstAccessMask);
    vkCmdPipelineBarrier2(cmd, &dep);
}

}  // namespace

ShadowSetup fitShadow(const Scene& scene, uint32_t mapSize) {
    ShadowSetup s;
    auto it = std::find_if(scene.lights.begin(), scene.lights.end(),
                           [](const Light& l) { return l.type == LightType::Directional; });
    if (it == scene.lights.end() || scene.instances.empty()) return s;
    glm::vec3 dir = glm::normalize(it->direction);
    glm::vec3 center = (scene.boundsMin + scene.boundsMax) * 0.5f;
    float radius = std::max(glm::length(scene.boundsMax - scene.boundsMin) * 0.5f, 1e-3f);
    glm::vec3 up = std::abs(dir.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    // The light camera sits 2r back from the centre: the sphere spans depths r..3r.
    glm::mat4 view = glm::lookAt(center - dir * (2.0f * radius), center, up);
    s.viewProj = orthographicShadowProjection(radius, radius, 3.0f * radius) * view;
    s.enabled = true;
    s.worldTexel = 2.0f * radius / float(std::max(mapSize, 1u));
    return s;
}

void Renderer::Impl::createGBufferPipelines() {
    gpu::GraphicsPipelineDesc shadow;
    shadow.vertexShader = "engine/shadow.vert";
    shadow.pushConstantBytes = sizeof(glm::mat4);
    shadow.depthFormat = kDepthFormat;
    // Every surface casts, whichever way it faces: single-sided planes must shadow too.
    shadow.cull = VK_CULL_MODE_NONE;
    shadow.depthBias = true;
    shadow.name = "render.shadow";
    shadowPipeline = gpu::createGraphicsPipeline(ctx, shadow);

    gpu::GraphicsPipelineDesc g;
    g.vertexShader = "engine/gbuffer.vert";
    g.fragmentShader = "engine/gbuffer.frag";
    g.bindings = kGBufferBindings;
    g.pushConstantBytes = sizeof(DrawConstants);
    g.colorFormats = {kAlbedoFormat, kNormalFormat, kEmissiveFormat, kMotionFormat};
    g.depthFormat = kDepthFormat;
    g.cull = kCullGltfBack;
    g.name = "render.gbuffer";
    gbufferCulled[0] = gpu::createGraphicsPipeline(ctx, g);
    g.cull = kCullGltfFront;
    g.name = "render.gbuffer.mirrored";
    gbufferCulled[1] = gpu::createGraphicsPipeline(ctx, g);
    g.cull = VK_CULL_MODE_NONE;
    g.name = "render.gbuffer.double_sided";
    gbufferDoubleSided = gpu::createGraphicsPipeline(ctx, g);

    frameConstants =
        gpu::Buffer(ctx, sizeof(FrameConstants),
                    VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false,
                    "render.frame_constants");
    // Fewer pipeline and descriptor switches: group draws by pipeline, then material.
    auto key = [&](const DrawItem& d) {
        return std::pair(int(cullKind(d, gpuScene.materials[d.material])), d.material);
    };
    std::stable_sort(gpuScene.draws.begin(), gpuScene.draws.end(),
                     [&](const DrawItem& a, const DrawItem& b) { return key(a) < key(b); });
}

void Renderer::Impl::recordShadow(VkCommandBuffer cmd, VkImageView map, uint32_t size) const {
    VkExtent2D extent{size, size};
    beginRendering(cmd, extent, {}, map);
    if (!gpuScene.draws.empty()) {
        shadowPipeline.bind(cmd);
        // Reversed-Z: "away from the light" is towards 0, hence the negative slope factor.
        vkCmdSetDepthBias(cmd, 0.0f, 0.0f, -1.5f);
        VkDeviceSize offset = 0;
        VkBuffer vb = gpuScene.vertices.get();
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        vkCmdBindIndexBuffer(cmd, gpuScene.indices.get(), 0, VK_INDEX_TYPE_UINT32);
        for (const DrawItem& d : gpuScene.draws) {
            glm::mat4 m = shadow.viewProj * d.model;
            vkCmdPushConstants(cmd, shadowPipeline.layout(), kGraphicsPushStages, 0, sizeof(m), &m);
            vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
        }
    }
    vkCmdEndRendering(cmd);
}

void Renderer::Impl::recordGBuffer(VkCommandBuffer cmd, const FrameInputs& frame, VkExtent2D extent,
                                   const std::vector<VkImageView>& colors,
                                   VkImageView depth) const {
    updateFrameConstants(cmd, frameConstants.get(),
                         {frame.camera.viewProj, frame.previousCamera.viewProj});
    beginRendering(cmd, extent, colors, depth);
    if (!gpuScene.draws.empty()) {
        VkDeviceSize offset = 0;
        VkBuffer vb = gpuScene.vertices.get();
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        vkCmdBindIndexBuffer(cmd, gpuScene.indices.get(), 0, VK_INDEX_TYPE_UINT32);
    }
    const gpu::Pipeline* bound = nullptr;
    uint32_t boundMaterial = ~0u;
    for (const DrawItem& d : gpuScene.draws) {
        const GpuMaterial& m = gpuScene.materials[d.material];
        CullKind kind = cullKind(d, m);
        const gpu::Pipeline* p = kind == CullKind::None
                                     ? &gbufferDoubleSided
                                     : &gbufferCulled[kind == CullKind::Front ? 1 : 0];
        if (p != bound) {
            p->bind(cmd);
            bound = p;
            boundMaterial = ~0u;  // descriptors are pushed per pipeline layout
        }
        if (d.material != boundMaterial) {
            VkSampler s = gpuScene.materialSampler;
            gpu::DescriptorWriter()
                .buffer(0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frameConstants.get())
                .sampled(1, m.baseColorView, s)
                .sampled(2, m.metallicRoughnessView, s)
                .sampled(3, m.normalView, s)
                .sampled(4, m.emissiveView, s)
                .push(ctx, cmd, *p);
            boundMaterial = d.material;
        }
        uint32_t drawFlags = (m.doubleSided ? kDrawDoubleSided : 0u) |
                             ((d.mirrored != kPipelineFrontIsGltfBack) ? kDrawInvertFacing : 0u);
        DrawConstants c{d.model, m.baseColor, glm::vec4(m.emissive, float(m.flags)),
                        glm::vec4(m.metallic, m.roughness, m.normalScale, float(drawFlags))};
        vkCmdPushConstants(cmd, p->layout(), kGraphicsPushStages, 0, sizeof(c), &c);
        vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
    }
    vkCmdEndRendering(cmd);
}

GBuffer Renderer::addGBufferPasses(FrameGraph& graph, const FrameInputs& frame) {
    Impl* impl = impl_.get();
    GBuffer out;
    if (impl->shadow.enabled) {
        struct ShadowData {
            TextureHandle map;
        };
        const uint32_t size = impl->options.shadowMapSize;
        const auto& s = graph.addPass<ShadowData>(
            "render.shadow", PassType::Raster,
            [&](PassBuilder& b, ShadowData& d) {
                TextureDesc desc{.width = size, .height = size, .format = kDepthFormat};
                d.map = b.write(b.create("render.shadow", desc), TextureUsage::DepthAttachment);
            },
            [impl, size](const ShadowData& d, PassContext& ctx) {
                impl->recordShadow(ctx.cmd(), ctx.view(d.map), size);
            });
        out.shadow = s.map;
    }

    struct GBufferData {
        GBuffer g;
    };
    const auto& g = graph.addPass<GBufferData>(
        "render.gbuffer", PassType::Raster,
        [&](PassBuilder& b, GBufferData& d) {
            auto target = [&](const char* name, VkFormat format, TextureUsage usage) {
                return b.write(b.create(name, TextureDesc{.format = format}), usage);
            };
            d.g.albedo = target("render.albedo", kAlbedoFormat, TextureUsage::ColorAttachment);
            d.g.normal = target("render.normal", kNormalFormat, TextureUsage::ColorAttachment);
            d.g.emissive =
                target("render.emissive", kEmissiveFormat, TextureUsage::ColorAttachment);
            d.g.motion = target("render.motion", kMotionFormat, TextureUsage::ColorAttachment);
            d.g.depth = target("render.depth", kDepthFormat, TextureUsage::DepthAttachment);
        },
        [impl, frame](const GBufferData& d, PassContext& ctx) {
            std::vector<VkImageView> colors = {ctx.view(d.g.albedo), ctx.view(d.g.normal),
                                               ctx.view(d.g.emissive), ctx.view(d.g.motion)};
            impl->recordGBuffer(ctx.cmd(), frame, ctx.extent(d.g.depth), colors,
                                ctx.view(d.g.depth));
        });
    GBuffer result = g.g;
    result.shadow = out.shadow;
    return result;
}

}  // namespace speculum::render
