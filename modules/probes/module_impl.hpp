// Private state of the probes module: the cube array, each probe's radiance cube (the faces as
// captured, with their box mip chain), the records, the capture runner and the update state.
#pragma once

#include "speculum/gpu/fg_executor.hpp"
#include "speculum/gpu/pipeline.hpp"
#include "speculum/gpu/resources.hpp"
#include "speculum/probes/probes.hpp"
#include "speculum/render/cube_filter.hpp"

#include <optional>

namespace speculum::probes {

struct Probes::Impl {
    const gpu::Context& ctx;
    render::Renderer& renderer;
    ProbeSettings settings;
    std::vector<ProbeInfo> probes;
    uint32_t faceSize = 8;  // the array's mip 0 face size: the largest probe resolution
    uint32_t mips = 2;      // down to 4x4, as the sky's cube
    gpu::Image cubes;       // cube array, SHADER_READ_ONLY_OPTIMAL between uses
    std::vector<gpu::Image> radiance;  // per probe: its resolution, full chain, GENERAL between uses
    std::vector<std::vector<gpu::Unique<VkImageView>>> targetViews;  // [probe][mip] cube views of the array
    gpu::Buffer records;
    gpu::Unique<VkSampler> sampler;  // trilinear clamp
    gpu::Unique<VkSampler> nearest;  // for texelFetch of the G-buffer (D32 has no linear filter here)
    gpu::Pipeline bounce;
    std::optional<gpu::Pipeline> debug[3];  // per DebugView (a specialization constant), made on first use
    render::CubeFilter filter;
    gpu::VulkanResourceAllocator allocator;
    gpu::VulkanFrameGraphExecutor executor;

    // Update state.
    bool baked = false;  // the array holds a bake: captures see it (else only the sky)
    std::vector<bool> pending;
    std::vector<bool> ready;  // prefiltered at least once: its record is in `records`
    size_t slice = 0;    // next time-sliced (probe, face): probe = slice / 6 over time-sliced probes
    size_t faces = 0;
    double ms = 0.0;

    Impl(const gpu::Context& c, render::Renderer& r, const ProbeSettings& s);
    void validate() const;
    void allocate();
    // Renders face `face` of probe `index` into its radiance cube (capture.cpp).
    void captureFace(size_t index, uint32_t face);
    // Box chain of the probe's radiance cube, then the GGX prefilter into its cube of the array.
    void prefilter(size_t index);
    // Writes the ready probes' records, in blend order, and returns how many.
    uint32_t writeRecords();
    uint32_t readyCount() const;
    void bakeAll(const std::vector<size_t>& which, const Progress& progress, size_t& done, size_t total);
};

}  // namespace speculum::probes
