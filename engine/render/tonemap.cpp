// render.tonemap: exposure, Narkowicz's ACES fit and the sRGB OETF into RGBA8 (tonemap.frag), a
// fullscreen triangle writing the colour attachment: lavapipe's rasteriser stores tiles far
// faster than compute imageStore.
#include "renderer_impl.hpp"

namespace speculum::render {
namespace {

struct TonemapConstants {
    glm::uvec2 size;
    float exposure;
};

}  // namespace

gpu::GraphicsPipelineDesc fullscreenPipelineDesc(const std::string& fragmentShader, VkFormat color,
                                                 const std::string& name) {
    gpu::GraphicsPipelineDesc d;
    d.vertexShader = "engine/fullscreen.vert";
    d.fragmentShader = fragmentShader;
    d.colorFormats = {color};
    d.depthTest = false;
    d.depthWrite = false;
    d.cull = VK_CULL_MODE_NONE;
    d.vertexInput = false;
    d.name = name;
    return d;
}

void beginFullscreenRendering(VkCommandBuffer cmd, VkExtent2D extent, VkImageView color) {
    VkRenderingAttachmentInfo attachment{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    attachment.imageView = color;
    attachment.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    attachment.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    attachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, extent};
    info.layerCount = 1;
    info.colorAttachmentCount = 1;
    info.pColorAttachments = &attachment;
    vkCmdBeginRendering(cmd, &info);
    VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
    VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
}

void Renderer::Impl::createTonemapPipeline() {
    gpu::GraphicsPipelineDesc d = fullscreenPipelineDesc("engine/tonemap.frag", kColorFormat, "render.tonemap");
    d.pushConstantBytes = sizeof(TonemapConstants);
    tonemapPipeline = gpu::createGraphicsPipeline(ctx, d);
}

void Renderer::Impl::recordTonemap(PassContext& pass, TextureHandle linear,
                                   TextureHandle out) const {
    VkCommandBuffer cmd = pass.cmd();
    VkExtent2D extent = pass.extent(out);
    beginFullscreenRendering(cmd, extent, pass.view(out));
    tonemapPipeline.bind(cmd);
    gpu::DescriptorWriter().sampled("linearTex", pass.view(linear), nearestSampler).push(ctx, cmd, tonemapPipeline);
    TonemapConstants c{{extent.width, extent.height}, options.exposure};
    vkCmdPushConstants(cmd, tonemapPipeline.layout(),
                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(c), &c);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
}

TextureHandle Renderer::addTonemapPass(FrameGraph& graph, TextureHandle linear) {
    struct TonemapData {
        TextureHandle linear;
        TextureHandle color;
    };
    Impl* impl = impl_.get();
    const auto& d = graph.addPass<TonemapData>(
        "render.tonemap", PassType::Raster,
        [&](PassBuilder& b, TonemapData& data) {
            data.linear = b.read(linear, TextureUsage::Sampled);
            data.color = b.write(b.create("render.color", TextureDesc{.format = kColorFormat}),
                                 TextureUsage::ColorAttachment);
        },
        [impl](const TonemapData& data, PassContext& ctx) {
            impl->recordTonemap(ctx, data.linear, data.color);
        });
    return d.color;
}

}  // namespace speculum::render
