// The GGX prefilter of a radiance cube, shared by the sky (Environment) and the local cubemap
// probes (modules/probes), so that a probe's mip m means exactly what the sky's mip m means:
// the split-sum prefilter (N = V = R) for perceptual roughness m / (mips - 1), alpha = roughness^2.
#pragma once

#include "speculum/gpu/pipeline.hpp"
#include "speculum/gpu/resources.hpp"

#include <span>
#include <vector>

namespace speculum::render {

// One piece of a prefilter: rows [firstRow, firstRow + rows) of faces [firstFace, firstFace +
// faces) of target mip `mip`. A whole mip is {mip, 0, 6, 0, its size}.
struct PrefilterSlice {
    uint32_t mip = 0, firstFace = 0, faces = 6, firstRow = 0, rows = 0;
    uint64_t work = 0;  // texel-samples: the cost unit of the budget below
};

// Cuts the prefilter of target mips [firstMip, mips) of a cube whose mip 0 face is `size` into
// steps of about `budget` texel-samples each (mip 0 takes one sample a texel, the rest
// `samples`): a mip that fits is one slice, a larger one goes in rows of one face, eight rows (a
// workgroup) at least, and consecutive slices share a step while their sum fits. Pure CPU: a
// time-sliced probe records one step per frame.
using PrefilterStep = std::vector<PrefilterSlice>;
std::vector<PrefilterStep> planPrefilterSteps(uint32_t size, uint32_t mips, uint32_t firstMip, uint32_t samples,
                                              uint64_t budget);

class CubeFilter {
public:
    explicit CubeFilter(const gpu::Context& ctx);

    // Box-filters `radiance` (a cube with a full mip chain to 1x1, every mip in GENERAL, mip 0
    // written) down to 1x1: the source that the prefilter reads with filtered importance
    // sampling. Leaves every mip in SHADER_READ_ONLY_OPTIMAL.
    void recordBoxChain(VkCommandBuffer cmd, const gpu::Image& radiance, VkSampler sampler) const;

    // Writes target mips [firstMip, mipViews.size()) from the box chain (SHADER_READ_ONLY):
    // mip m is the GGX prefilter for roughness m / (mips - 1); mip 0, when asked for, is the
    // bilinear radiance at each texel's centre (one sample of a 1e-4 lobe), so a target of
    // another face size than the radiance is resampled. `mipViews` are cube views in GENERAL,
    // `size` the target's mip 0 face size.
    void recordPrefilter(VkCommandBuffer cmd, const gpu::Image& radiance, VkSampler sampler,
                         std::span<const VkImageView> mipViews, uint32_t size, uint32_t firstMip,
                         uint32_t samples) const;
    // One slice of that prefilter (planPrefilterSlices); `mips` is the target's mip count.
    void recordPrefilterSlice(VkCommandBuffer cmd, const gpu::Image& radiance, VkSampler sampler,
                              VkImageView mipView, uint32_t size, uint32_t mips, const PrefilterSlice& slice,
                              uint32_t samples) const;

private:
    const gpu::Context& ctx_;
    gpu::Pipeline downsample_, prefilter_;
};

}  // namespace speculum::render
