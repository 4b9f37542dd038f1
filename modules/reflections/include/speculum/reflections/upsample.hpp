// Joint bilateral upsampling (Kopf et al. 2007) of a low-resolution image to full resolution, guided by full-resolution depth and normals and by a low-resolution guide that
// says which full pixel each low sample stands for (modules/reflections/shaders/upsample.comp explains
// the weights). The reflections module upsamples its half-resolution reflection and, in a pass
// of its own that the graph culls unless something reads it, its method image with it; it is a pass of its own so that it is tested alone (tests/gpu/upsample_test.cpp)
// and reusable by other half-resolution passes.
#pragma once

#include "speculum/framegraph.hpp"
#include "speculum/gpu/context.hpp"
#include "speculum/gpu/pipeline.hpp"
#include "speculum/render/renderer.hpp"


namespace speculum::reflections {

struct UpsampleInputs {
    TextureHandle depth;   // full: reversed-Z depth (D32 or R32), read with texelFetch
    TextureHandle normal;  // full: xyz normal, w roughness
    // low (RGBA32F): xyz the world position of the full pixel it traced, w +-(1 + its index in
    // its 2x2, x + 2 y), positive when it reflects (modules/reflections/shaders/guide.glsl)
    TextureHandle guide;
    TextureHandle low;                 // RGBA16F, the guide's size
    glm::mat4 invViewProj;             // of the frame the depth belongs to
    glm::vec3 eye;
};

class BilateralUpsampler {
public:
    explicit BilateralUpsampler(const gpu::Context& ctx);
    // `pass` (reflections.upsample...): an RGBA16F image the size of `depth`, named `name`.
    TextureHandle addPass(FrameGraph& graph, const UpsampleInputs& in, const std::string& pass,
                          const std::string& name) const;

private:
    const gpu::Context& ctx_;
    gpu::Pipeline pipeline_;
    gpu::Unique<VkSampler> nearest_;
};

}  // namespace speculum::reflections
