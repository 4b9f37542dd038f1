// The GGX prefilter of a radiance cube, shared by the sky (Environment) and the local cubemap
// probes (modules/probes), so that a probe's mip m means exactly what the sky's mip m means:
// the split-sum prefilter (N = V = R) for perceptual roughness m / (mips - 1), alpha = roughness^2.
#pragma once

#include "speculum/gpu/pipeline.hpp"
#include "speculum/gpu/resources.hpp"

#include <span>

namespace speculum::render {

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

private:
    const gpu::Context& ctx_;
    gpu::Pipeline downsample_, prefilter_;
};

}  // namespace speculum::render
