// Private state of the reflections module: pipelines, samplers, the per-frame uniforms, the
// material table and the history images that live across frames.
#pragma once

#include "speculum/reflections/reflections.hpp"

#include <array>
#include <optional>

#include <glm/glm.hpp>

namespace speculum::reflections {

// std140 twin of ReflectionFrame in shaders/reflections/common.glsl.
struct FrameUniforms {
    glm::mat4 viewProj;
    glm::mat4 invViewProj;
    glm::mat4 prevViewProj;
    glm::mat4 view;
    glm::vec4 camera;
    glm::vec4 size;
    glm::vec4 trace;
    glm::vec4 trace2;
    glm::vec4 cone;
    glm::vec4 fade;
    glm::vec4 fade2;
    glm::uvec4 modes;
    glm::uvec4 modes2;
};

// The previous frame's final lit image and its depth: frame-graph histories (the graph swaps
// them and knows whether the previous one was written).
struct ReflectionHistory {
    gpu::HistoryImages color;
    gpu::HistoryImages depth;
    uint32_t width = 0, height = 0;
    bool valid() const { return color.history().valid() && depth.history().valid(); }
    void invalidate() {
        color.history().invalidate();
        depth.history().invalidate();
    }
};

struct Reflections::Impl {
    const gpu::Context& ctx;
    render::Renderer& renderer;
    gpu::Pipeline hiz, visibility, reproject, colorDown, resolve, hizView;
    // One pipeline per tracer and per debug view (specialization constants), made on first
    // use: lavapipe runs both sides of a uniform branch, so the untaken tracer's loops cost the
    // trace about 5% and the debug views' fetches cost the plain composite about 40%.
    std::array<std::optional<gpu::Pipeline>, 2> traces;
    std::array<std::optional<gpu::Pipeline>, kDebugViewCount> composites;
    const gpu::Pipeline& trace(TraceMode mode);
    const gpu::Pipeline& composite(DebugView view);
    gpu::Unique<VkSampler> nearest;
    gpu::Unique<VkSampler> trilinear;
    gpu::Buffer uniforms;
    gpu::Buffer materials;
    uint32_t materialCount = 0;
    ReflectionHistory history;
    // Bound when the host gives no probes (ReflectionInputs::probes left empty): one black cube
    // and one zeroed record, blended zero times.
    gpu::Image noProbeCubes;
    gpu::Buffer noProbeRecords;
    probes::ProbeSet importNoProbes(FrameGraph& g) const;
    // This frame's imports of the histories (addColorPyramid reads previous, addHistory writes current).
    HistoryHandles historyColor, historyDepth;

    Impl(const gpu::Context& c, render::Renderer& r);
    void writeUniforms(const ReflectionInputs& in, const ReflectionSettings& s, uint32_t w, uint32_t h,
                       uint32_t levels);
    void ensureHistory(uint32_t w, uint32_t h);

    // Passes, in frame order (passes.cpp).
    TextureHandle addHiZ(FrameGraph& g, TextureHandle depth, uint32_t levels);
    TextureHandle addVisibility(FrameGraph& g, TextureHandle hiz, uint32_t levels);
    TextureHandle addColorPyramid(FrameGraph& g, const ReflectionInputs& in, TextureHandle visibility,
                                  uint32_t levels);
    TextureHandle addTrace(FrameGraph& g, const ReflectionInputs& in, TextureHandle hiz, TraceMode mode);
    void addResolve(FrameGraph& g, const ReflectionInputs& in, ReflectionOutputs& out);
    struct Composited {
        TextureHandle shown;    // the lit image, or the debug view
        TextureHandle history;  // the lit image
    };
    Composited addComposite(FrameGraph& g, const ReflectionInputs& in, const ReflectionOutputs& out,
                            DebugView view);
    void addHistory(FrameGraph& g, TextureHandle lit, TextureHandle depth);
    TextureHandle addHiZView(FrameGraph& g, TextureHandle hiz);

    gpu::DescriptorWriter writer() const;  // binding 0: the frame uniforms
    void dispatch(PassContext& pc, const gpu::Pipeline& p, gpu::DescriptorWriter& w, VkExtent2D extent,
                  const void* push = nullptr, uint32_t pushBytes = 0) const;
};

}  // namespace speculum::reflections
