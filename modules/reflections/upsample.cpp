// reflections.upsample: see speculum/reflections/upsample.hpp and modules/reflections/shaders/upsample.comp.
#include "speculum/reflections/upsample.hpp"

#include "reflections/shaders/upsample.h"

namespace speculum::reflections {
namespace {

constexpr VkShaderStageFlags kCompute = VK_SHADER_STAGE_COMPUTE_BIT;
constexpr VkFormat kFormat = VK_FORMAT_R16G16B16A16_SFLOAT;

static_assert(sizeof(shader::UpsampleParams) == 96, "std430 push constants");

}  // namespace

BilateralUpsampler::BilateralUpsampler(const gpu::Context& ctx)
    : ctx_(ctx),
      pipeline_(gpu::createComputePipeline(ctx, "reflections/upsample.comp", sizeof(shader::UpsampleParams),
                                           "reflections.upsample")),
      nearest_(gpu::createSampler(ctx, VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, false)) {}

TextureHandle BilateralUpsampler::addPass(FrameGraph& g, const UpsampleInputs& in, const std::string& pass,
                                          const std::string& name) const {
    struct Data {
        TextureHandle depth, normal, guide, low, full;
    };
    shader::UpsampleParams params{};
    params.invViewProj = in.invViewProj;
    params.eye = glm::vec4(in.eye, 0.0f);
    const auto& d = g.addPass<Data>(
        pass, PassType::Compute,
        [&](PassBuilder& b, Data& data) {
            data.depth = b.read(in.depth, TextureUsage::Sampled);
            data.normal = b.read(in.normal, TextureUsage::Sampled);
            data.guide = b.read(in.guide, TextureUsage::Sampled);
            data.low = b.read(in.low, TextureUsage::Sampled);
            data.full = b.write(b.create(name, TextureDesc{.format = kFormat, .relativeTo = in.depth}),
                                TextureUsage::StorageWrite);
        },
        [this, base = params](const Data& data, PassContext& pc) {
            VkExtent2D full = pc.extent(data.full), low = pc.extent(data.guide);
            shader::UpsampleParams params = base;
            params.size = glm::vec4(float(full.width), float(full.height), float(low.width), float(low.height));
            gpu::DescriptorWriter w;
            w.sampled("depthTex", pc.view(data.depth), nearest_.get())
                .sampled("normalTex", pc.view(data.normal), nearest_.get())
                .sampled("guideTex", pc.view(data.guide), nearest_.get())
                .sampled("lowTex", pc.view(data.low), nearest_.get())
                .storage("fullOut", pc.view(data.full));
            pipeline_.bind(pc.cmd());
            w.push(ctx_, pc.cmd(), pipeline_);
            vkCmdPushConstants(pc.cmd(), pipeline_.layout(), kCompute, 0, sizeof(params), &params);
            vkCmdDispatch(pc.cmd(), (full.width + 7) / 8, (full.height + 7) / 8, 1);
        });
    return d.full;
}

}  // namespace speculum::reflections
