// render.depth_prepass and render.gbuffer.
//
// The prepass writes render.depth alone; the G-buffer then tests GREATER_OR_EQUAL against it
// with depth writes off (DepthRead), so every G-buffer pixel is shaded once and the colour
// targets are created only after render.shadow_mask, in memory the shadow map no longer needs.
// Both vertex shaders compute gl_Position with the same precise expression, so the depths match
// bit for bit.
//
// Alpha modes (MASK, BLEND) are ignored: every surface is opaque. Only TEXCOORD_0 is used.
#include "renderer_impl.hpp"
#include "speculum/render/frustum.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <tuple>

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

// Which of the three G-buffer pipelines a draw uses.
enum class CullKind : uint8_t { Back, Front, None };

// A view reflected in a plane (FrameInputs::mirrored) flips every triangle's winding, as a
// mirrored transform flips its own: the two cancel.
CullKind cullKind(const DrawItem& d, const GpuMaterial& m, bool mirroredView = false) {
    if (m.doubleSided) return CullKind::None;
    return d.mirrored != mirroredView ? CullKind::Front : CullKind::Back;
}

// readOnlyDepth: test against the prepass's depth, which stays as it is.
void beginRendering(VkCommandBuffer cmd, VkExtent2D extent, const std::vector<VkImageView>& colors,
                    VkImageView depth, bool readOnlyDepth = false) {
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
    depthInfo.imageLayout = readOnlyDepth ? VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL
                                          : VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depthInfo.loadOp = readOnlyDepth ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;
    depthInfo.storeOp = readOnlyDepth ? VK_ATTACHMENT_STORE_OP_NONE : VK_ATTACHMENT_STORE_OP_STORE;
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

const gpu::Pipeline& pipelineFor(const gpu::Pipeline (&pipelines)[3], const DrawItem& d,
                                 const GpuMaterial& m, bool mirroredView) {
    return pipelines[int(cullKind(d, m, mirroredView))];
}

}  // namespace

void bindSceneGeometry(VkCommandBuffer cmd, const SceneGpu& scene) {
    if (scene.draws.empty()) return;
    VkDeviceSize offset = 0;
    VkBuffer vb = scene.vertices.get();
    vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
    vkCmdBindIndexBuffer(cmd, scene.indices.get(), 0, VK_INDEX_TYPE_UINT32);
}

void Renderer::Impl::createGBufferPipelines() {
    constexpr VkCullModeFlags kCull[3] = {kCullGltfBack, kCullGltfFront, VK_CULL_MODE_NONE};
    constexpr const char* kSuffix[3] = {"", ".mirrored", ".double_sided"};
    gpu::GraphicsPipelineDesc prepass;
    prepass.vertexShader = "engine/depth_prepass.vert";
    // The shader declares the whole DrawConstants block; the prepass pushes only the model.
    prepass.pushConstantBytes = sizeof(DrawConstants);
    prepass.depthFormat = kDepthFormat;

    gpu::GraphicsPipelineDesc g;
    g.vertexShader = "engine/gbuffer.vert";
    g.pushConstantBytes = sizeof(DrawConstants);
    g.colorFormats = {kAlbedoFormat, kNormalFormat, kEmissiveFormat, kMotionFormat};
    g.depthFormat = kDepthFormat;
    g.depthWrite = false;  // GREATER_OR_EQUAL against the prepass: equal depths pass
    for (int i = 0; i < 3; ++i) {
        prepass.cull = g.cull = kCull[i];
        prepass.name = std::string("render.depth_prepass") + kSuffix[i];
        prepassPipelines[i] = gpu::createGraphicsPipeline(ctx, prepass);
        g.fragmentShader = "engine/gbuffer.frag";
        g.name = std::string("render.gbuffer") + kSuffix[i];
        gbufferPipelines[0][i] = gpu::createGraphicsPipeline(ctx, g);
        g.fragmentShader = "engine/gbuffer_untextured.frag";
        g.name = std::string("render.gbuffer.untextured") + kSuffix[i];
        gbufferPipelines[1][i] = gpu::createGraphicsPipeline(ctx, g);
    }

    frameConstants =
        gpu::Buffer(ctx, sizeof(FrameConstants),
                    VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false,
                    "render.frame_constants");
    // Fewer pipeline and descriptor switches: group draws by pipeline, then material.
    auto key = [&](const DrawItem& d) {
        const GpuMaterial& m = gpuScene.materials[d.material];
        return std::tuple(int(cullKind(d, m)), m.untextured, d.material);
    };
    std::stable_sort(gpuScene.draws.begin(), gpuScene.draws.end(),
                     [&](const DrawItem& a, const DrawItem& b) { return key(a) < key(b); });
}

void Renderer::Impl::recordDepthPrepass(VkCommandBuffer cmd, const FrameInputs& frame,
                                        VkExtent2D extent, VkImageView depth) const {
    updateFrameConstants(cmd, frameConstants.get(),
                         {frame.camera.viewProj, frame.previousCamera.viewProj});
    beginRendering(cmd, extent, {}, depth);
    bindSceneGeometry(cmd, gpuScene);
    const gpu::Pipeline* bound = nullptr;
    const Frustum view = frustumOf(frame.camera.viewProj);
    for (const DrawItem& d : gpuScene.draws) {
        if (!d.drawnIn(frame.primaryView) || outside(view, d.worldMin, d.worldMax)) continue;
        const gpu::Pipeline* p = &pipelineFor(prepassPipelines, d, gpuScene.materials[d.material], frame.mirrored);
        if (p != bound) {
            p->bind(cmd);
            gpu::DescriptorWriter().buffer("frame", frameConstants.get()).push(ctx, cmd, *p);
            bound = p;
        }
        vkCmdPushConstants(cmd, p->layout(), kGraphicsPushStages, 0, sizeof(d.model), &d.model);
        vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
    }
    vkCmdEndRendering(cmd);
}

void Renderer::Impl::recordGBuffer(VkCommandBuffer cmd, const FrameInputs& frame, VkExtent2D extent,
                                   const std::vector<VkImageView>& colors, VkImageView depth) const {
    beginRendering(cmd, extent, colors, depth, true);
    bindSceneGeometry(cmd, gpuScene);
    const gpu::Pipeline* bound = nullptr;
    uint32_t boundMaterial = ~0u;
    // The prepass's culling exactly, so that every depth it wrote is shaded here.
    const Frustum view = frustumOf(frame.camera.viewProj);
    for (const DrawItem& d : gpuScene.draws) {
        if (!d.drawnIn(frame.primaryView) || outside(view, d.worldMin, d.worldMax)) continue;
        const GpuMaterial& m = gpuScene.materials[d.material];
        const gpu::Pipeline* p = &pipelineFor(gbufferPipelines[m.untextured ? 1 : 0], d, m, frame.mirrored);
        if (p != bound) {
            p->bind(cmd);
            bound = p;
            boundMaterial = ~0u;  // descriptors are pushed per pipeline layout
        }
        if (d.material != boundMaterial) {
            VkSampler s = gpuScene.materialSampler;
            gpu::DescriptorWriter()
                .buffer("frame", frameConstants.get())
                .sampled("baseColorTex", m.baseColorView, s)
                .sampled("metallicRoughnessTex", m.metallicRoughnessView, s)
                .sampled("normalTex", m.normalView, s)
                .sampled("emissiveTex", m.emissiveView, s)
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

TextureHandle Renderer::Impl::addDepthPrepass(FrameGraph& graph, const FrameInputs& frame) {
    struct PrepassData {
        TextureHandle depth;
    };
    const auto& d = graph.addPass<PrepassData>(
        "render.depth_prepass", PassType::Raster,
        [&](PassBuilder& b, PrepassData& data) {
            data.depth = b.write(b.create("render.depth", TextureDesc{.format = kDepthFormat}),
                                 TextureUsage::DepthAttachment);
        },
        [this, frame](const PrepassData& data, PassContext& ctx) {
            recordDepthPrepass(ctx.cmd(), frame, ctx.extent(data.depth), ctx.view(data.depth));
        });
    return d.depth;
}

GBuffer Renderer::addGBufferPasses(FrameGraph& graph, const FrameInputs& frame) {
    Impl* impl = impl_.get();
    TextureHandle depth = impl->addDepthPrepass(graph, frame);
    TextureHandle mask = impl->addShadowPasses(graph, frame, depth);
    struct GBufferData {
        GBuffer g;
    };
    const auto& g = graph.addPass<GBufferData>(
        "render.gbuffer", PassType::Raster,
        [&](PassBuilder& b, GBufferData& d) {
            auto target = [&](const char* name, VkFormat format) {
                return b.write(b.create(name, TextureDesc{.format = format}),
                               TextureUsage::ColorAttachment);
            };
            d.g.albedo = target("render.albedo", kAlbedoFormat);
            d.g.normal = target("render.normal", kNormalFormat);
            d.g.emissive = target("render.emissive", kEmissiveFormat);
            d.g.motion = target("render.motion", kMotionFormat);
            d.g.depth = b.read(depth, TextureUsage::DepthRead);
        },
        [impl, frame](const GBufferData& d, PassContext& ctx) {
            std::vector<VkImageView> colors = {ctx.view(d.g.albedo), ctx.view(d.g.normal),
                                               ctx.view(d.g.emissive), ctx.view(d.g.motion)};
            impl->recordGBuffer(ctx.cmd(), frame, ctx.extent(d.g.depth), colors, ctx.view(d.g.depth));
        });
    GBuffer result = g.g;
    result.shadowMask = mask;
    return result;
}

}  // namespace speculum::render
