// Private state of the reflections module: pipelines, samplers, the per-frame uniforms, the
// material table and the history images that live across frames.
#pragma once

#include "speculum/reflections/reflections.hpp"
#include "speculum/reflections/upsample.hpp"

#include <array>
#include <initializer_list>
#include <map>
#include <optional>

#include <glm/glm.hpp>

#include <cstddef>

#include "reflections/shaders/frame.h"
#include "reflections/shaders/tiles.h"

namespace speculum::reflections {

// The frame uniforms, declared once for C++ and GLSL (modules/reflections/shaders/frame.h).
using FrameUniforms = shader::ReflectionFrame;
static_assert(offsetof(FrameUniforms, eye) == 256 && offsetof(FrameUniforms, znear) == 268);
static_assert(offsetof(FrameUniforms, size) == 272 && offsetof(FrameUniforms, maxIterations) == 288);
static_assert(offsetof(FrameUniforms, traceMode) == 368 && offsetof(FrameUniforms, temporalAlpha) == 400);
static_assert(offsetof(FrameUniforms, cmoCount) == 416);
static_assert(offsetof(FrameUniforms, planarCount) == 448);
static_assert(sizeof(FrameUniforms) == 468, "std140 layout");

// The Hi-Z pyramid's texels: the cell's farthest and closest depth (reversed-Z).
inline constexpr VkFormat kHiZFormat = VK_FORMAT_R32G32_SFLOAT;

// The previous frame's final lit image and its depth: frame-graph histories (the graph swaps
// them and knows whether the previous one was written), written in place by the passes that
// make them (no copy).
// With reflections.temporal, the accumulated reflection and the normals and roughness it was
// accumulated on (the temporal pass writes both, no copy).
struct ReflectionHistory {
    // The lit image with this frame's reflections: reflections.composite writes it in place.
    gpu::HistoryImages color;
    // The Hi-Z pyramid: its level 0 is the depth (hiz_first.comp copies it texel for texel), so
    // the previous frame's depth is the previous pyramid's level 0. Both were copies in a
    // reflections.history pass: 0.5 ms of the module's 1.2 at 1080p on an H100 (MEASUREMENTS).
    gpu::HistoryImages hiz;
    gpu::HistoryImages reflection;
    gpu::HistoryImages normal;
    // reflections.ray_budget=quarter: the refreshed reflection and its normals (refresh.comp),
    // made on the first frame that asks for them.
    gpu::HistoryImages refresh;
    gpu::HistoryImages refreshNormal;
    uint32_t width = 0, height = 0;
    bool valid() const { return color.history().valid() && hiz.history().valid(); }
    bool temporalValid() const {
        return hiz.history().valid() && reflection.history().valid() && normal.history().valid();
    }
    bool refreshValid() const {
        return hiz.history().valid() && refresh.history().valid() && refreshNormal.history().valid();
    }
    void invalidate() {
        refresh.history().invalidate();
        refreshNormal.history().invalidate();
        color.history().invalidate();
        hiz.history().invalidate();
        reflection.history().invalidate();
        normal.history().invalidate();
    }
};

struct Reflections::Impl {
    const gpu::Context& ctx;
    render::Renderer& renderer;
    gpu::Pipeline hiz, hizFirst, visibility, colorDown, hizView, temporal, refresh;
    BilateralUpsampler upsampler;
    // One pipeline per tracer and per debug view (specialization constants), made on first
    // use: lavapipe runs both sides of a uniform branch, so the untaken tracer's loops cost the
    // trace about 5% and the debug views' fetches cost the plain composite about 40%.
    // Trace and resolve per resolution (half reads the guide's pixel) and glossy mode too.
    // Each also per tile mode (tiles.h: the whole screen, a work list, a fill list, the resolve's
    // lookup list).
    static constexpr size_t kTileModes = 6;  // tiles.h, kTileMode*
    std::array<std::optional<gpu::Pipeline>, 8 * kTileModes> traces;
    std::array<std::optional<gpu::Pipeline>, 4 * kTileModes> resolves;
    // Per view, temporal, tiled, tile scale and list (composite.comp's constants).
    std::map<uint32_t, gpu::Pipeline> composites;
    const gpu::Pipeline& trace(TraceMode mode, Resolution resolution, GlossyMode glossy, uint32_t tileMode);
    const gpu::Pipeline& resolve(Resolution resolution, GlossyMode glossy, uint32_t tileMode);
    // reflections.cmo_trace per resolution and tracer; the scene's lights are its constants.
    std::array<std::optional<gpu::Pipeline>, 4 * kTileModes> cmoTraces;
    const gpu::Pipeline& cmoTrace(Resolution resolution, bool linear, uint32_t tileMode);
    // reflections.classify per resolution and ray budget.
    std::array<std::optional<gpu::Pipeline>, 4> classifies;
    const gpu::Pipeline& classify(Resolution resolution, RayBudget budget);
    struct CompositeVariant {
        DebugView view = DebugView::None;
        bool temporal = false;
        bool tiled = false;     // on the reflective tiles only (after reflections.composite_copy)
        bool half = false;      // tiles of the half-size trace: 16x16 full pixels each
    };
    const gpu::Pipeline& composite(const CompositeVariant& v, uint32_t list);
    // reflections.reproject per tile mode (the whole screen, or the reflective tiles after
    // reflections.reproject_copy), tile scale (half resolution's tiles cover 16x16 full pixels)
    // and list.
    std::map<uint32_t, gpu::Pipeline> reprojects;
    std::map<uint32_t, gpu::Pipeline> lookupFulls;  // by tile mode and list
    const gpu::Pipeline& lookupFull(uint32_t tileMode, uint32_t list);
    std::map<uint32_t, gpu::Pipeline> hitReuses;  // by tile mode, CMOs, CMO tracer and list
    const gpu::Pipeline& hitReuse(uint32_t tileMode, bool cmos, bool linear, uint32_t list);
    const gpu::Pipeline& reproject(uint32_t tileMode, bool half, uint32_t list);
    gpu::Unique<VkSampler> nearest;
    gpu::Unique<VkSampler> trilinear;
    gpu::Buffer uniforms;
    gpu::Buffer materials;
    uint32_t materialCount = 0;
    ReflectionHistory history;
    // The last frame's settings: a change resets the temporal history (a new setting would
    // otherwise fade in over temporal_alpha's frames and the bench would score the blend).
    std::optional<ReflectionSettings> lastSettings;
    uint32_t frameIndex = 0;
    uint32_t framesSinceReset = 0;  // frames with a valid colour history in a row
    static constexpr uint32_t kBounceFillFrames = 3;
    // Bound when the host gives no probes (ReflectionInputs::probes left empty): one black cube
    // and one zeroed record, blended zero times.
    gpu::Image noProbeCubes;
    gpu::Buffer noProbeRecords;
    probes::ProbeSet importNoProbes(FrameGraph& g) const;
    // The same for planar probes: a black 4x4 layer and one zeroed record, read zero times.
    gpu::Image noPlanarImages;
    gpu::Buffer noPlanarRecords;
    probes::PlanarSet importNoPlanar(FrameGraph& g) const;
    // This frame's imports of the histories: addHiZ writes historyHiz.current, the composite
    // historyColor.current; the reprojections read their previous images.
    HistoryHandles historyColor, historyHiz, historyReflection, historyNormal;

    Impl(const gpu::Context& c, render::Renderer& r);
    // s: what the passes run with; asked: the host's settings (a change of them resets the histories).
    void writeUniforms(const ReflectionInputs& in, const ReflectionSettings& s, const ReflectionSettings& asked,
                       uint32_t w, uint32_t h, uint32_t levels);
    void ensureHistory(uint32_t w, uint32_t h, bool refreshImages);

    // Passes, in frame order (passes.cpp).
    // The Hi-Z pyramid; `visibility` gets the visibility pyramid with its level 1 written (by the
    // first pass, hiz_first.comp), invalid for a 1x1 view.
    TextureHandle addHiZ(FrameGraph& g, TextureHandle depth, uint32_t levels, TextureHandle& visibility);
    // The visibility pyramid's levels 2 and up, after `level1`.
    TextureHandle addVisibility(FrameGraph& g, TextureHandle hiz, TextureHandle level1, uint32_t levels);
    // Level 0 (reflections.reproject) runs on the reflective tiles' footprints with `s.tiles`.
    struct Classified;
    TextureHandle addColorPyramid(FrameGraph& g, const ReflectionInputs& in, TextureHandle visibility,
                                  uint32_t levels, const Classified& tiles, const ReflectionSettings& s);
    TextureHandle addReproject(FrameGraph& g, const ReflectionInputs& in, const Classified& tiles,
                               const ReflectionSettings& s, TextureHandle copied, const TextureDesc& pyramidDesc);
    // reflections.classify (and reflections.tile_clear before it): the tile lists (tiles.h); at
    // half resolution also the guide (which full pixel each half pixel traces,
    // modules/reflections/shaders/guide.glsl).
    struct Classified {
        BufferHandle tiles;
        TextureHandle guide;  // half resolution only
        // Half resolution with tiles (reflections.footprint_args): the dispatches of the lists
        // kListResolveRay and kListLookup for the full-resolution passes on them (reproject,
        // composite), with y = 4: one workgroup per 8x8 block of a tile's 16x16 footprint.
        BufferHandle footprint;
    };
    Classified addClassify(FrameGraph& g, const ReflectionInputs& in, TextureHandle hiz, const ReflectionSettings& s);
    // The lists a footprint buffer has a dispatch for, in its slots' order (kListCmo's only in the
    // buffer made after the trace, `cmoList`: reflections.hit_reuse's CMO variant).
    static constexpr std::array<uint32_t, 3> kFootprintLists{shader::kListResolveRay, shader::kListLookup,
                                                             shader::kListCmo};
    BufferHandle addFootprintArgs(FrameGraph& g, BufferHandle classified, bool cmoList = false);
    // reflections.trace: the hit image, at the trace's size (half-size at half resolution).
    // It appends its tiles to the CMO trace's lists (tiles.tiles is the new version).
    TextureHandle addTrace(FrameGraph& g, const ReflectionInputs& in, TextureHandle hiz, Classified& tiles,
                           const ReflectionSettings& s);
    // One per-pixel pass's dispatches: with reflections.tiles, each (pipeline, list) pair by
    // indirect dispatch from the tile lists; without, the first pipeline over `extent`.
    struct TileRun {
        const gpu::Pipeline* pipeline;
        uint32_t list;
    };
    // `footprint`: Classified::footprint where valid (a full-resolution pass at half resolution).
    void dispatchTiles(PassContext& pc, const gpu::DescriptorWriter& w, BufferHandle tiles, bool tiled,
                       std::initializer_list<TileRun> runs, VkExtent2D extent, BufferHandle footprint = {}) const;
    // reflections.cmo_trace: what screen space leaves, through the CMOs (out.cmo, out.cmoInfo).
    void addCmoTrace(FrameGraph& g, const ReflectionInputs& in, const Classified& tiles, const ReflectionSettings& s,
                     ReflectionOutputs& out);
    void addResolve(FrameGraph& g, const ReflectionInputs& in, const Classified& tiles, const ReflectionSettings& s,
                    ReflectionOutputs& out);
    // reflections.lookup_full (half resolution): the pixels whose trace pixel found no
    // screen-space and no CMO hit take the chain's lookups at full resolution over `upsampled`
    // (lookup_full.comp); `halfMethod`: the resolve's method image. Returns the new version.
    TextureHandle addLookupFull(FrameGraph& g, const ReflectionInputs& in, const Classified& tiles,
                                const ReflectionSettings& s, TextureHandle hiz, TextureHandle halfMethod,
                                TextureHandle upsampled);
    // reflections.hit_reuse (half resolution): the mirror pixels their 2x2 did not trace take
    // their own screen-space hit, found from the neighbours' hits, over `upsampled`
    // (hit_reuse.comp). Returns the new version.
    TextureHandle addHitReuse(FrameGraph& g, const ReflectionInputs& in, const Classified& tiles,
                              const ReflectionSettings& s, const ReflectionOutputs& out, TextureHandle halfMethod,
                              TextureHandle halfReflection, TextureHandle upsampled);
    // One of its passes: the CMO variant or the other, on `footprint`'s lists (none: the screen).
    TextureHandle addHitReusePass(FrameGraph& g, const ReflectionInputs& in, const Classified& tiles,
                                  const ReflectionOutputs& out, TextureHandle halfMethod, TextureHandle halfReflection,
                                  TextureHandle upsampled, bool cmos, bool linear, BufferHandle footprint);
    // The fallback chain past screen space, as the passes that evaluate it (resolve, lookup_full)
    // read it: the local probes, the planar probes and their grounds, and (bindChain) the sky.
    struct ChainReads {
        TextureHandle probeCubes, planar, ground, probeDistances;
        BufferHandle probeRecords, planarRecords, groundRecords;
    };
    static ChainReads readChain(PassBuilder& b, const probes::ProbeSet& set);
    void bindChain(gpu::DescriptorWriter& w, PassContext& pc, const ChainReads& r) const;
    // A CMO set, as the CMO trace and hit reuse's CMO variant read it.
    struct CmoReads {
        TextureHandle distance, radiance, attr, albedo;
        BufferHandle records;
    };
    static CmoReads readCmos(PassBuilder& b, const probes::CmoSet& set);
    void bindCmos(gpu::DescriptorWriter& w, PassContext& pc, const CmoReads& r) const;
    // What the passes that keep a history (temporal, refresh) read alike: the surface, its motion,
    // their own history with its normals, and the previous depth (shaders/reprojection.glsl).
    struct HistoryReads {
        TextureHandle hiz, normal, emissive, motion, history, historyNormal, historyDepth;
    };
    HistoryReads readHistory(PassBuilder& b, const ReflectionInputs& in, TextureHandle hiz, const HistoryHandles& color,
                             const HistoryHandles& normal) const;
    gpu::DescriptorWriter historyWriter(PassContext& pc, const HistoryReads& r) const;
    // reflections.refresh (ray_budget=quarter): from the half-size reflection `half`, each pixel's
    // own last traced value where its history holds, else the bilateral upsampling (refresh.comp);
    // returns the full-size refreshed image.
    TextureHandle addRefresh(FrameGraph& g, const ReflectionInputs& in, TextureHandle hiz, const ReflectionOutputs& out,
                             TextureHandle half);
    HistoryHandles historyRefresh, historyRefreshNormal;
    // Accumulates `reflection` (full size) over frames into the history; returns the accumulated
    // image. `distance`: the reflected distance at the trace's size (ReflectionOutputs::distance).
    TextureHandle addTemporal(FrameGraph& g, const ReflectionInputs& in, TextureHandle hiz, TextureHandle reflection,
                              TextureHandle distance);
    // Returns the image shown: the lit image, or the debug view. The lit image with this frame's
    // own reflection goes into historyColor.current (the same image when they are one).
    // `raw`: with temporal accumulation, this frame's reflection (out.reflection is the accumulated one).
    TextureHandle addComposite(FrameGraph& g, const ReflectionInputs& in, const ReflectionOutputs& out,
                            const Classified& tiles, const ReflectionSettings& s, TextureHandle raw);
    // `pass`: the lit image copied whole into level 0 of new textures (name, desc), which a tiled
    // pass then overwrites on its tiles only. A transfer: 0.6 ms at 960x540 on lavapipe, where a
    // compute pass that writes the same (the reprojection's fill variant) took 9.
    struct CopyTarget {
        std::string name;
        TextureDesc desc;
        TextureHandle into;  // valid: write this (a history's current image) instead of a new texture
    };
    std::vector<TextureHandle> addLitCopy(FrameGraph& g, const std::string& pass, TextureHandle lit,
                                          const std::vector<CopyTarget>& targets);
    // New textures cleared to a constant by a transfer pass, for a tiled pass that then writes
    // its work tiles only. On lavapipe invocations cost whatever they do: the trace's fill variant
    // (one store each) cost 1.6-2.8 ms at 960x540, a clear about 1 (MEASUREMENTS.md, issue 23,
    // 2026-12-07).
    struct ClearTarget {
        std::string name;
        TextureDesc desc;
        VkClearColorValue value;
    };
    std::vector<TextureHandle> addClear(FrameGraph& g, const std::string& pass, const std::vector<ClearTarget>& targets);
    TextureHandle addHiZView(FrameGraph& g, TextureHandle hiz);

    gpu::DescriptorWriter writer() const;  // the frame constants, rf and rfm (common.glsl)
    // writer() and the pixel's surface as material.glsl and the passes that trace, resolve,
    // guide and accumulate read it: the Hi-Z pyramid `hiz` (level 0: depth), `normalTex`
    // (normal and roughness), `emissiveTex` (flags and material index), the `MaterialTable`.
    gpu::DescriptorWriter surfaceWriter(PassContext& pc, TextureHandle hiz, TextureHandle normal,
                                        TextureHandle emissive) const;
    void dispatch(PassContext& pc, const gpu::Pipeline& p, gpu::DescriptorWriter& w, VkExtent2D extent,
                  const void* push = nullptr, uint32_t pushBytes = 0) const;
};

}  // namespace speculum::reflections
