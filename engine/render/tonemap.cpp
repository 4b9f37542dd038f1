// render.tonemap: exposure, Narkowicz's ACES fit and the sRGB OETF into RGBA8 (tonemap.comp).
#include "renderer_impl.hpp"

namespace speculum::render {
namespace {

struct TonemapConstants {
    glm::uvec2 size;
    float exposure;
};

}  // namespace

void Renderer::Impl::createTonemapPipeline() {
    tonemapPipeline = gpu::createComputePipeline(
        ctx, "engine/tonemap.comp",
        {
            {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_COMPUTE_BIT},
            {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_COMPUTE_BIT},
        },
        sizeof(TonemapConstants), "render.tonemap");
}

void Renderer::Impl::recordTonemap(PassContext& pass, TextureHandle linear,
                                   TextureHandle out) const {
    VkCommandBuffer cmd = pass.cmd();
    VkExtent2D extent = pass.extent(out);
    tonemapPipeline.bind(cmd);
    gpu::DescriptorWriter()
        .sampled(0, pass.view(linear), nearestSampler)
        .storage(1, pass.view(out))
        .push(ctx, cmd, tonemapPipeline);
    TonemapConstants c{{extent.width, extent.height}, options.exposure};
    vkCmdPushConstants(cmd, tonemapPipeline.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(c),
                       &c);
    vkCmdDispatch(cmd, (extent.width + 7) / 8, (extent.height + 7) / 8, 1);
}

TextureHandle Renderer::addTonemapPass(FrameGraph& graph, TextureHandle linear) {
    struct TonemapData {
        TextureHandle linear;
        TextureHandle color;
    };
    Impl* impl = impl_.get();
    const auto& d = graph.addPass<TonemapData>(
        "render.tonemap", PassType::Compute,
        [&](PassBuilder& b, TonemapData& data) {
            data.linear = b.read(linear, TextureUsage::Sampled);
            data.color = b.write(b.create("render.color", TextureDesc{.format = kColorFormat}),
                                 TextureUsage::StorageWrite);
        },
        [impl](const TonemapData& data, PassContext& ctx) {
            impl->recordTonemap(ctx, data.linear, data.color);
        });
    return d.color;
}

}  // namespace speculum::render
