// Box mip chain and GGX prefilter of a radiance cube (ibl_downsample.comp, ibl_prefilter.comp):
// the environment and the probes record the same two steps.
#include "speculum/render/cube_filter.hpp"

#include <algorithm>

namespace speculum::render {
namespace {

constexpr VkShaderStageFlags kCompute = VK_SHADER_STAGE_COMPUTE_BIT;
constexpr uint32_t kGroup = 8;  // local size of the ibl_*.comp shaders

uint32_t groups(uint32_t n) {
    return (n + kGroup - 1) / kGroup;
}

// Push constants; layouts mirror the shaders' push_constant blocks.
struct DownsamplePush {
    uint32_t size;
};
struct PrefilterPush {
    uint32_t size, samples;
    float alpha;
    uint32_t sourceSize;
    float sourceMips;
    uint32_t firstRow, firstFace;
};

}  // namespace

CubeFilter::CubeFilter(const gpu::Context& ctx)
    : ctx_(ctx),
      downsample_(gpu::createComputePipeline(ctx, "engine/ibl_downsample.comp", sizeof(DownsamplePush),
                                             "render.environment.downsample")),
      prefilter_(gpu::createComputePipeline(ctx, "engine/ibl_prefilter.comp", sizeof(PrefilterPush),
                                            "render.environment.prefilter")) {}

void CubeFilter::recordBoxChain(VkCommandBuffer cmd, const gpu::Image& radiance, VkSampler sampler) const {
    const uint32_t size = radiance.desc().width;
    auto toReadOnly = [&](uint32_t mip) {
        gpu::transition(cmd, radiance.get(), radiance.aspect(), VK_IMAGE_LAYOUT_GENERAL,
                        VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, mip, 1);
    };
    toReadOnly(0);
    downsample_.bind(cmd);
    for (uint32_t m = 1; m < radiance.desc().mips; ++m) {
        const uint32_t mipSize = std::max(1u, size >> m);
        gpu::DescriptorWriter()
            .sampled("source", radiance.mipView(m - 1), sampler)
            .storage("target", radiance.mipView(m))
            .push(ctx_, cmd, downsample_);
        DownsamplePush p{mipSize};
        vkCmdPushConstants(cmd, downsample_.layout(), kCompute, 0, sizeof(p), &p);
        vkCmdDispatch(cmd, groups(mipSize), groups(mipSize), 6);
        toReadOnly(m);
    }
}

std::vector<PrefilterStep> planPrefilterSteps(uint32_t size, uint32_t mips, uint32_t firstMip, uint32_t samples,
                                              uint64_t budget) {
    std::vector<PrefilterSlice> slices;
    budget = std::max<uint64_t>(budget, 1);
    for (uint32_t m = firstMip; m < mips; ++m) {
        const uint32_t mipSize = std::max(1u, size >> m);
        const uint64_t row = uint64_t(mipSize) * (m == 0 ? 1u : samples);  // one row of one face
        if (row * mipSize * 6 <= budget) {
            slices.push_back({m, 0, 6, 0, mipSize, row * mipSize * 6});
            continue;
        }
        // Whole workgroups of rows: a dispatch covers rows in steps of kGroup, and a slice must not
        // write its neighbour's rows (mip sizes are powers of two, so this tiles every face).
        uint32_t rows = uint32_t(std::clamp<uint64_t>(budget / row, 1, mipSize));
        if (rows < mipSize) rows = std::min(mipSize, std::max(kGroup, rows / kGroup * kGroup));
        for (uint32_t f = 0; f < 6; ++f)
            for (uint32_t y = 0; y < mipSize; y += rows) {
                const uint32_t n = std::min(rows, mipSize - y);
                slices.push_back({m, f, 1, y, n, row * n});
            }
    }
    std::vector<PrefilterStep> steps;
    uint64_t sum = 0;
    for (const PrefilterSlice& s : slices) {
        if (steps.empty() || sum + s.work > budget) {
            steps.emplace_back();
            sum = 0;
        }
        steps.back().push_back(s);
        sum += s.work;
    }
    return steps;
}

void CubeFilter::recordPrefilter(VkCommandBuffer cmd, const gpu::Image& radiance, VkSampler sampler,
                                 std::span<const VkImageView> mipViews, uint32_t size, uint32_t firstMip,
                                 uint32_t samples) const {
    const uint32_t mips = uint32_t(mipViews.size());
    for (uint32_t m = firstMip; m < mips; ++m) {
        const uint32_t mipSize = std::max(1u, size >> m);
        recordPrefilterSlice(cmd, radiance, sampler, mipViews[m], size, mips, {m, 0, 6, 0, mipSize}, samples);
    }
}

void CubeFilter::recordPrefilterSlice(VkCommandBuffer cmd, const gpu::Image& radiance, VkSampler sampler,
                                      VkImageView mipView, uint32_t size, uint32_t mips, const PrefilterSlice& slice,
                                      uint32_t samples) const {
    const uint32_t m = slice.mip;
    const uint32_t mipSize = std::max(1u, size >> m);
    const float roughness = mips > 1 ? float(m) / float(mips - 1) : 0.0f;
    prefilter_.bind(cmd);
    gpu::DescriptorWriter()
        .sampled("radiance", radiance.view(), sampler)
        .storage("target", mipView)
        .push(ctx_, cmd, prefilter_);
    // Mip 0 is the mirror image: one sample of a lobe too narrow to reach past the texel.
    PrefilterPush p{mipSize,
                    m == 0 ? 1u : samples,
                    m == 0 ? 1e-4f : roughness * roughness,
                    radiance.desc().width,
                    float(radiance.desc().mips),
                    slice.firstRow,
                    slice.firstFace};
    vkCmdPushConstants(cmd, prefilter_.layout(), kCompute, 0, sizeof(p), &p);
    vkCmdDispatch(cmd, groups(mipSize), groups(slice.rows), slice.faces);
}

}  // namespace speculum::render
