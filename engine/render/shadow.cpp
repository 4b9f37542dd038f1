// render.shadow and render.shadow_mask.
//
// Shadow map: orthographic projection fitted to the scene's bounds as the first directional
// light sees them, reversed-Z like the main view (1 nearest the light, cleared to 0,
// GREATER_OR_EQUAL), D32. Bias: a slope-scaled raster bias away from the light plus a
// normal offset and constant bias at lookup time (shadow_mask.frag).
//
// The map is fitted to the scene's bounds, not to the view: it is drawn once into an image kept
// across frames (renderer_impl.hpp, shadowMap) and drawn again only when a caster hides or its
// size changes. The mask pass resolves it into one byte of filtered visibility per pixel right
// after the depth prepass, and lighting reads one texel instead of filtering.
#include "renderer_impl.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <limits>

namespace speculum::render {
namespace {

struct MaskConstants {
    glm::mat4 invViewProj;
    glm::vec4 cameraPosition;
    glm::uvec4 size;
};
static_assert(sizeof(MaskConstants) <= 128, "push constants must fit lavapipe's 128 bytes");

gpu::Unique<VkSampler> createCompareSampler(const gpu::Context& ctx) {
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    info.magFilter = info.minFilter = VK_FILTER_NEAREST;  // textureGather ignores the filter
    info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    info.addressModeU = info.addressModeV = info.addressModeW =
        VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    info.compareEnable = VK_TRUE;
    // Reversed-Z: the reference (receiver depth + bias) is lit when >= the stored occluder.
    info.compareOp = VK_COMPARE_OP_GREATER_OR_EQUAL;
    VkSampler s;
    gpu::check(vkCreateSampler(ctx.device(), &info, nullptr, &s), "vkCreateSampler");
    return {ctx.device(), s, vkDestroySampler};
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
    glm::mat4 view = glm::lookAt(center - dir * (2.0f * radius), center, up);
    // Fitted to the bounds' eight corners seen from the light rather than to the bounding
    // sphere: the same map covers less empty space, so its texels are smaller.
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (int i = 0; i < 8; ++i) {
        glm::vec3 corner((i & 1) ? scene.boundsMax.x : scene.boundsMin.x,
                         (i & 2) ? scene.boundsMax.y : scene.boundsMin.y,
                         (i & 4) ? scene.boundsMax.z : scene.boundsMin.z);
        glm::vec3 p = glm::vec3(view * glm::vec4(corner, 1.0f));
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    // Square texels; a margin of a few texels keeps normal-offset lookups at the edges inside.
    float half = std::max(std::max(hi.x - lo.x, hi.y - lo.y) * 0.5f, 1e-3f);
    half *= 1.0f + 8.0f / float(std::max(mapSize, 1u));
    glm::vec2 mid = (glm::vec2(lo) + glm::vec2(hi)) * 0.5f;
    view = glm::translate(glm::mat4(1.0f), glm::vec3(-mid, 0.0f)) * view;
    // The view looks down -z; a 1% margin keeps the nearest and farthest surfaces unclipped.
    float depthMargin = 0.01f * (hi.z - lo.z) + 1e-3f;
    float znear = -hi.z - depthMargin, zfar = -lo.z + depthMargin;
    s.viewProj = orthographicShadowProjection(half, znear, zfar) * view;
    s.enabled = true;
    s.toLight = -dir;
    s.worldTexel = 2.0f * half / float(std::max(mapSize, 1u));
    s.depthTexel = s.worldTexel / (zfar - znear);
    return s;
}

void Renderer::Impl::createShadowResources() {
    gpu::GraphicsPipelineDesc desc;
    desc.vertexShader = "engine/shadow.vert";
    desc.pushConstantBytes = sizeof(glm::mat4);
    desc.depthFormat = kDepthFormat;
    // Every surface casts, whichever way it faces: single-sided planes must shadow too.
    desc.cull = VK_CULL_MODE_NONE;
    desc.depthBias = true;
    desc.name = "render.shadow";
    shadowPipeline = gpu::createGraphicsPipeline(ctx, desc);

    gpu::GraphicsPipelineDesc mask =
        fullscreenPipelineDesc("engine/shadow_mask.frag", VK_FORMAT_R8_UNORM, "render.shadow_mask");
    mask.pushConstantBytes = sizeof(MaskConstants);
    shadowMaskPipeline = gpu::createGraphicsPipeline(ctx, mask);
    shadowCompareSampler = createCompareSampler(ctx);

    // Bound by lighting when there is no directional light: nothing is shadowed then.
    gpu::ImageDesc dummy{.width = 1,
                         .height = 1,
                         .format = VK_FORMAT_R8_UNORM,
                         .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT};
    dummyShadowMask = gpu::Image(ctx, dummy, "render.shadow_mask.none");
    const uint8_t lit = 255;
    gpu::uploadImage(ctx, dummyShadowMask, std::as_bytes(std::span(&lit, 1)), false);
}

void Renderer::Impl::recordShadow(VkCommandBuffer cmd, VkImageView map, uint32_t size) const {
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depth.imageView = map;
    depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depth.clearValue.depthStencil = {0.0f, 0};  // reversed-Z: nothing in front of the light
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, {size, size}};
    info.layerCount = 1;
    info.pDepthAttachment = &depth;
    vkCmdBeginRendering(cmd, &info);
    VkViewport viewport{0.0f, 0.0f, float(size), float(size), 0.0f, 1.0f};
    VkRect2D scissor{{0, 0}, {size, size}};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    if (!gpuScene.draws.empty()) {
        shadowPipeline.bind(cmd);
        // Reversed-Z: "away from the light" is towards 0, hence the negative slope factor.
        vkCmdSetDepthBias(cmd, 0.0f, 0.0f, -1.5f);
        bindSceneGeometry(cmd, gpuScene);
        for (const DrawItem& d : gpuScene.draws) {
            if (!d.drawnIn(false)) continue;
            glm::mat4 m = shadow.viewProj * d.model;
            vkCmdPushConstants(cmd, shadowPipeline.layout(),
                               VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                               sizeof(m), &m);
            vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, d.vertexOffset, 0);
        }
    }
    vkCmdEndRendering(cmd);
}

void Renderer::Impl::recordShadowMask(PassContext& pass, const FrameInputs& frame,
                                      TextureHandle depth, TextureHandle map,
                                      TextureHandle out) const {
    VkCommandBuffer cmd = pass.cmd();
    VkExtent2D extent = pass.extent(out);
    beginFullscreenRendering(cmd, extent, pass.view(out));
    shadowMaskPipeline.bind(cmd);
    gpu::DescriptorWriter()
        .sampled("depthTex", pass.view(depth), nearestSampler)
        .sampled("shadowMap", pass.view(map), shadowCompareSampler)
        .buffer("SceneShadowBuffer", sceneShadow.get())
        .push(ctx, cmd, shadowMaskPipeline);
    MaskConstants c{frame.camera.invViewProj, glm::vec4(frame.camera.position, 0.0f),
                    glm::uvec4(extent.width, extent.height, 0, 0)};
    vkCmdPushConstants(cmd, shadowMaskPipeline.layout(),
                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(c), &c);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
}

TextureHandle Renderer::Impl::addShadowPasses(FrameGraph& graph, const FrameInputs& frame,
                                              TextureHandle depth) {
    if (!shadow.enabled) return {};
    struct ShadowData {
        TextureHandle map;
    };
    const uint32_t size = options.shadowMapSize;
    if (shadowMap.get() == VK_NULL_HANDLE || shadowMap.desc().width != size) {
        shadowMap = gpu::Image(ctx,
                               {.width = size,
                                .height = size,
                                .format = kDepthFormat,
                                .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT},
                               "render.shadow_map");
        shadowDrawn = 0;
    }
    // Drawn once per change; every later frame (and planar probe view) reads it as it is.
    const bool current = shadowDrawn == shadowCasters;
    const VkImageLayout held = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    TextureHandle map = graph.importTexture(
        "render.shadow_map", {.width = size, .height = size, .format = kDepthFormat},
        {shadowMap.get(), current ? held : VK_IMAGE_LAYOUT_UNDEFINED, held, shadowMap.desc().usage});
    if (!current) {
        const auto& s = graph.addPass<ShadowData>(
            "render.shadow", PassType::Raster,
            [&](PassBuilder& b, ShadowData& d) { d.map = b.write(map, TextureUsage::DepthAttachment); },
            [this, size, casters = shadowCasters](const ShadowData& d, PassContext& ctx) {
                recordShadow(ctx.cmd(), ctx.view(d.map), size);
                shadowDrawn = casters;  // recorded: the frames after this one read it
            });
        map = s.map;
    }
    struct MaskData {
        TextureHandle depth, map, mask;
    };
    const auto& m = graph.addPass<MaskData>(
        "render.shadow_mask", PassType::Raster,
        [&](PassBuilder& b, MaskData& d) {
            d.depth = b.read(depth, TextureUsage::Sampled);
            d.map = b.read(map, TextureUsage::Sampled);
            TextureDesc desc{.format = VK_FORMAT_R8_UNORM};
            d.mask =
                b.write(b.create("render.shadow_mask", desc), TextureUsage::ColorAttachment);
        },
        [this, frame](const MaskData& d, PassContext& ctx) {
            recordShadowMask(ctx, frame, d.depth, d.map, d.mask);
        });
    return m.mask;
}

}  // namespace speculum::render
