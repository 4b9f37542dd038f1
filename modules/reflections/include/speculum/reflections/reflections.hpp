// The reflections module: Hi-Z screen-space cone-traced reflections (Uludag, GPU Pro 5) with an
// environment fallback, composited with the split-sum DFG term. One entry point,
// Reflections::addPasses, takes typed frame-graph handles and returns typed handles; the
// module's README explains the technique, its failure modes and its settings.
#pragma once

#include "speculum/app/module.hpp"
#include "speculum/framegraph.hpp"
#include "speculum/gpu/context.hpp"
#include "speculum/gpu/pipeline.hpp"
#include "speculum/gpu/resources.hpp"
#include "speculum/probes/probes.hpp"
#include "speculum/render/renderer.hpp"
#include "speculum/settings.hpp"

#include <memory>
#include <vector>

namespace speculum::reflections {

// The module's settings table (reflections.*, ReflectionSettings::fields()): the one description
// that drives JSON, --set, the editor and the tests.
std::vector<SettingDesc> settingsTable();
// What the module registers with its host: the table, its AOVs, its debug views.
app::ModuleInfo moduleInfo();

enum class TraceMode : uint32_t { HiZ = 0, Linear = 1 };
// How much of a pixel screen space covers: `hit` (a hit covers fully, fades aside) or
// `visibility` (the cone's accumulated visibility, as in the book).
enum class CoverageMode : uint32_t { Hit = 0, Visibility = 1 };
// reflections.resolution: where trace and resolve run (the upsampler brings half to full).
enum class Resolution : uint32_t { Full = 0, Half = 1 };
// reflections.ray_budget: a ray per pixel each frame, or one per 2x2 rotating over four frames
// (the half-size grid; reflections.refresh takes the rest from the history).
enum class RayBudget : uint32_t { Full = 0, Quarter = 1 };
// reflections.glossy: cone-traced mirror hit, or GGX samples reused across neighbours.
enum class GlossyMode : uint32_t { Cone = 0, Stochastic = 1 };
// reflections.cmo_trace: the min/max hierarchy per face, or constant steps (the baseline).
enum class CmoTraceMode : uint32_t { Hierarchical = 0, Linear = 1 };
enum class DebugView : uint32_t { None = 0, Iterations, HitMask, Coverage, Method, HiZ, Reflection, Cmo, Tiles };
inline constexpr size_t kDebugViewCount = 9;

// The values of settingsTable(), whose rows bind these fields: fromSettings<ReflectionSettings>()
// fills them, and the defaults are the table's (the constructor writes them), so that no second
// copy of a name or a default can drift from the table.
struct ReflectionSettings {
    ReflectionSettings();
    static const SettingFields<ReflectionSettings>& fields();
    bool operator==(const ReflectionSettings&) const = default;

    bool enabled;
    bool screenSpace;  // off: no ray is traced, the chain starts at the probes
    TraceMode trace;
    int maxIterations;
    int linearPreSteps;
    int hizStartLevel;
    int hizStopLevel;
    float linearStride;
    int linearMaxSteps;
    int refineSteps;
    float thickness;
    int coneSamples;
    CoverageMode coverage;
    float maxRoughness;
    float edgeFade;
    float cameraFadeStart;
    float cameraFadeEnd;
    float distanceFadeStart;
    float distanceFadeEnd;
    bool multiBounce;
    float hitReflectMaxRoughness;  // screen-space hits on mirrors: shaded for the ray (resolve.comp)
    bool probes;  // local probes in the fallback chain (off: screen space, then the sky)
    bool cmos;    // CMOs in the chain, before the local probes
    CmoTraceMode cmoTrace;
    int cmoMaxIterations;
    float cmoLinearStep;
    float cmoThickness;
    float cmoMaxDistance;
    int cmoBounces;
    float cmoMaxRoughness;
    bool cmoPassBehind;  // reflections.cmo_unresolved=pass_behind
    Resolution resolution;
    bool fullResLookups;  // half resolution: lookups at full resolution (reflections.lookup_full)
    bool hitReuse;  // half resolution: mirror pixels find their own hit from the neighbours' (reflections.hit_reuse)
    bool tiles;  // reflections.classify's tile lists drive trace, cmo_trace and resolve
    RayBudget rayBudget;  // quarter: traces on the half-size grid whatever `resolution` says
    GlossyMode glossy;
    bool temporal;
    float temporalAlpha;
    float temporalClip;
    DebugView debugView;
    int debugHizMip;
};

struct ReflectionInputs {
    render::GBuffer gbuffer;
    TextureHandle lit;  // this frame's lit HDR image (render.lighting)
    render::FrameInputs frame;
    // The probes module's output (Probes::addPasses on the same graph); empty: no probes, what
    // screen space leaves goes to the sky.
    probes::ProbeSet probes;
};

struct ReflectionOutputs {
    TextureHandle lit;          // lit + reflection * DFG on reflective pixels (or a debug view)
    TextureHandle reflection;   // RGBA16F: rgb pre-Fresnel reflection radiance, a screen-space share
    TextureHandle method;       // RGBA16F: r screen space, g local probes, b sky, a CMOs (sum 1)
    TextureHandle distance;     // R16F at the trace's size: the reflected distance the temporal pass
                                // reprojects by (m; 0 unknown, kSkyDistance the sky)
    TextureHandle cmo;          // RGBA16F at the trace's size: rgb radiance CMOs found, a first hit's distance (0 none)
    TextureHandle cmoInfo;      // RGBA16F at the trace's size: iterations, CMO that hit (1-based), status, bounces
    TextureHandle hit;          // RGBA32F: xy hit pixel position, z hit depth (< 0 miss), w iterations
    TextureHandle hiz;          // RG32F pyramid: x farthest, y closest depth per cell (reversed-Z)
    TextureHandle visibility;   // R8 pre-integrated visibility pyramid
    TextureHandle colorPyramid; // RGBA16F pre-convolved colour pyramid
    TextureHandle hizView;      // RGBA16F view of one Hi-Z level (only when asked for)
    TextureHandle guide;        // half resolution only: RGBA32F, modules/reflections/shaders/guide.glsl
};

class Reflections {
public:
    // Needs the renderer for its environment (the fallback) and the scene's materials.
    Reflections(const gpu::Context& ctx, render::Renderer& renderer);
    ~Reflections();
    Reflections(const Reflections&) = delete;
    Reflections& operator=(const Reflections&) = delete;

    // Adds reflections.* passes after render.lighting, which must leave the specular ambient of
    // reflective pixels to the module (LightingOptions::moduleSpecular): the composite adds it.
    // `hizView` adds the Hi-Z level view.
    ReflectionOutputs addPasses(FrameGraph& graph, const ReflectionInputs& inputs,
                                const ReflectionSettings& settings, bool hizView = false);
    // Forgets the previous frame (camera cuts, scene changes): the next colour pyramid is built
    // from that frame's own lit image.
    void resetHistory();

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace speculum::reflections
