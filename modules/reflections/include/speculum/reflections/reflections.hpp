// The reflections module: Hi-Z screen-space cone-traced reflections (Uludag, GPU Pro 5) with an
// environment fallback, composited with the split-sum DFG term. One entry point,
// Reflections::addPasses, takes typed frame-graph handles and returns typed handles; the
// module's README explains the technique, its failure modes and its settings.
#pragma once

#include "speculum/framegraph.hpp"
#include "speculum/gpu/context.hpp"
#include "speculum/gpu/pipeline.hpp"
#include "speculum/gpu/resources.hpp"
#include "speculum/render/renderer.hpp"
#include "speculum/settings.hpp"

#include <memory>
#include <vector>

namespace speculum::reflections {

// The module's settings table (reflections.*): the one description that drives JSON, --set,
// the editor and the tests.
std::vector<SettingDesc> settingsTable();

enum class TraceMode : uint32_t { HiZ = 0, Linear = 1 };
// How much of a pixel screen space covers: `hit` (a hit covers fully, fades aside) or
// `visibility` (the cone's accumulated visibility, as in the book).
enum class CoverageMode : uint32_t { Hit = 0, Visibility = 1 };
enum class DebugView : uint32_t { None = 0, Iterations, HitMask, Coverage, Method, HiZ, Reflection };
inline constexpr size_t kDebugViewCount = 7;

struct ReflectionSettings {
    bool enabled = true;
    TraceMode trace = TraceMode::HiZ;
    int maxIterations = 64;
    int linearPreSteps = 2;
    int hizStartLevel = 2;
    int hizStopLevel = 0;
    float linearStride = 2.0f;
    int linearMaxSteps = 512;
    int refineSteps = 5;
    float thickness = 0.08f;
    int coneSamples = 8;
    CoverageMode coverage = CoverageMode::Hit;
    float maxRoughness = 0.6f;
    float edgeFade = 0.05f;
    float cameraFadeStart = -0.2f;
    float cameraFadeEnd = -0.6f;
    float distanceFadeStart = 40.0f;
    float distanceFadeEnd = 60.0f;
    bool multiBounce = true;
    DebugView debugView = DebugView::None;
    int debugHizMip = 3;

    static ReflectionSettings from(const Settings& settings);
};

struct ReflectionInputs {
    render::GBuffer gbuffer;
    TextureHandle lit;  // this frame's lit HDR image (render.lighting)
    render::FrameInputs frame;
};

struct ReflectionOutputs {
    TextureHandle lit;          // lit + reflection * DFG on reflective pixels (or a debug view)
    TextureHandle reflection;   // RGBA16F: rgb pre-Fresnel reflection radiance, a screen-space share
    TextureHandle method;       // RGBA16F: r screen space, g probes (later), b environment weight
    TextureHandle hit;          // RGBA32F: xy hit pixel position, z hit depth (< 0 miss), w iterations
    TextureHandle hiz;          // RG32F pyramid: x farthest, y closest depth per cell (reversed-Z)
    TextureHandle visibility;   // R8 pre-integrated visibility pyramid
    TextureHandle colorPyramid; // RGBA16F pre-convolved colour pyramid
    TextureHandle hizView;      // RGBA16F view of one Hi-Z level (only when asked for)
};

class Reflections {
public:
    // Needs the renderer for its environment (the fallback) and the scene's materials.
    Reflections(const gpu::Context& ctx, render::Renderer& renderer);
    ~Reflections();
    Reflections(const Reflections&) = delete;
    Reflections& operator=(const Reflections&) = delete;

    // Adds reflections.* passes after render.lighting. `hizView` adds the Hi-Z level view.
    ReflectionOutputs addPasses(FrameGraph& graph, const ReflectionInputs& inputs,
                                const ReflectionSettings& settings, bool hizView = false);
    // Off: render.lighting keeps the specular ambient of reflective pixels and the history is
    // forgotten; on: the module composites it (the default once constructed).
    void setActive(bool active);
    // Forgets the previous frame (camera cuts, scene changes): the next colour pyramid is built
    // from that frame's own lit image.
    void resetHistory();

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace speculum::reflections
