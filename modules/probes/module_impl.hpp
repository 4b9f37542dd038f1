// Private state of the probes module: the cube array, each probe's radiance cube (the faces as
// captured, with their box mip chain), the records, the capture runner and the update state.
#pragma once

#include "speculum/gpu/fg_executor.hpp"
#include "speculum/gpu/pipeline.hpp"
#include "speculum/gpu/resources.hpp"
#include "speculum/probes/probes.hpp"
#include "speculum/render/cube_filter.hpp"

#include <optional>

#include "probes/shaders/cmo.h"

namespace speculum::probes {

// How messages name a probe's node: nodes[N] "name" (probes.cpp).
std::string probeName(const Scene& scene, int node);

// The frame-graph description of an image the module keeps across frames (imported each use).
inline TextureDesc descOf(const gpu::Image& image) {
    const gpu::ImageDesc& d = image.desc();
    return {.width = d.width, .height = d.height, .format = d.format, .mips = d.mips, .layers = d.layers, .cube = d.cube};
}

struct Probes::Impl {
    const gpu::Context& ctx;
    render::Renderer& renderer;
    ProbeSettings settings;
    std::vector<ProbeInfo> probes;
    uint32_t faceSize = 8;  // the array's mip 0 face size: the largest probe resolution
    uint32_t mips = 2;      // down to 4x4, as the sky's cube
    gpu::Image cubes;       // cube array, SHADER_READ_ONLY_OPTIMAL between uses
    // The cube array one bounce short of `cubes` (GENERAL between uses), for captures whose
    // surfaces are already one reflection deep: a planar probe's mirrored view. A surface in
    // bake k reflects bake k - 1, so the main view's reflection of `cubes` (bake N, N =
    // probes.bounces) stops N reflections deep, as the reference's --bounces N does; the planar
    // image's own surfaces must then reflect bake N - 1 (gallery.main's mirror band +1.6 dB).
    // A CMO's faces are one reflection deep too, but reflecting `below` there lost 0.07-0.11
    // dB on cornell_mirrors' views (MEASUREMENTS.md, issue 24, 2026-12-04): they keep `cubes`.
    // Made only with planar probes and N >= 2 (with N = 1 both are bake 1); each probe's layers
    // are copied from `cubes` whenever it finishes a bake, except in the last round of the first
    // bake. Re-bakes after that (a moved probe, a taken gem) copy their new bake: one bounce
    // deeper, but never stale.
    gpu::Image below;
    // The captured distance (m) from each probe's capture point, a cube of the array per probe at
    // the array's face size, mip 0 only, RGBA16F: r the distance (65504 at the sky), gba a smooth
    // metal's normal times its F0 (probes.distance_store; GENERAL between uses): narrow lobes
    // find their hit on it instead of on the proxy (probes.glsl).
    gpu::Image distances;
    gpu::Pipeline distanceStore;
    bool lastRound = false;  // update(): the first bake's last round, which `below` does not keep
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
    std::vector<int> relocating;   // moveProbe, recapture: the next step of its cycle, -1 none
    std::vector<bool> movedAgain;  // moved since its re-capture began: one more cycle
    bool baked = false;  // the array holds a bake: captures see it (else only the sky)
    std::vector<bool> pending;
    std::vector<bool> ready;  // prefiltered at least once: its record is in `records`
    // Time-sliced cycle: the time-sliced probes in turn, each six captures (steps 0-5) and then
    // its prefilter's steps (6 ...), one step per update.
    std::vector<render::PrefilterStep> steps;      // the prefilter of one cube of the array, sliced
    std::vector<render::PrefilterStep> wholePlan;  // the same in one step of whole mips (bakes)
    size_t slicedProbe = 0;
    size_t slicedStep = 0;
    size_t timeSlicedCycle() const { return 6 + steps.size(); }
    size_t faces = 0;
    double ms = 0.0;

    // CMOs (cmo.cpp): arrays of 6 layers per CMO at the largest CMO resolution, full chains.
    struct CmoState {
        std::vector<CmoInfo> list;
        uint32_t faceSize = 16, mips = 5;
        gpu::Image radiance, distance, attr, albedo;
        // Per mip: a 2D-array view of every layer (storage writes and the hierarchy's reads).
        std::vector<gpu::Unique<VkImageView>> radianceMips, distanceMips, attrMips, albedoMips;
        gpu::Buffer records, mirrors;
        uint32_t mirrorCount = 1;
        gpu::Pipeline store, reduce;
        std::vector<bool> pending, ready;
        std::vector<bool> blind;  // baked and saw only sky: left out of tracing
        size_t faces = 0;         // CMO faces captured and their GPU milliseconds
        double ms = 0.0;
        std::vector<int> relocating;  // moveProbe, recapture: the next step of its cycle, -1 none
        std::vector<bool> movedAgain; // moved since its re-capture began: one more cycle
        size_t slice = 0;
    };
    std::optional<CmoState> cmo;

    // Planar probes (planar.cpp): one 2D array, a layer per probe at the largest probe's size for
    // the current view; a probe below it renders at the mip of its own height.
    struct PlanarState {
        std::vector<PlanarInfo> list;
        gpu::Image images;  // RGBA16F, GENERAL between uses
        gpu::Buffer records;
        gpu::Pipeline store;
        uint32_t width = 0, height = 0;  // the view the images were made for
        uint32_t rendered = 0;           // records written by the last renderPlanar
        int sinceRender = 0;             // renderPlanar calls that reused the images (interval)
        bool valid = false;              // the images and records are of this size's last render
        double ms = 0.0;
        // The grounds (PlanarGround, probe.h): a layer each at probes.planar_ground's size, GENERAL
        // between uses; rendered before the bakes that read them (update()), view-independent.
        gpu::Image ground;
        gpu::Buffer groundRecords;
        gpu::Pipeline groundStore;
        uint32_t groundCount = 0;  // records the last renderGrounds wrote
        bool groundValid = false;  // false: update() renders them before its bakes
    };
    PlanarState planar;

    Impl(const gpu::Context& c, render::Renderer& r, const ProbeSettings& s);
    void validate() const;
    void allocate();
    // Renders face `face` of probe `index` into its radiance cube (capture.cpp).
    void captureFace(size_t index, uint32_t face);
    // Step `step` of `plan` (steps, or wholePlan: all mips at once), the GGX prefilter of probe
    // `index`'s radiance cube into its cube of the array: the first also box-filters the radiance
    // cube; after the last, the probe is ready.
    void prefilter(size_t index, const std::vector<render::PrefilterStep>& plan, size_t step);
    // Step `step` of a time-sliced cycle of probe `index`: a face, then the prefilter's steps;
    // true when it was the cycle's last.
    bool cycleStep(size_t index, size_t step);
    // Writes the ready probes' records, in blend order, and returns how many.
    uint32_t writeRecords();
    uint32_t readyCount() const;
    void bakeAll(const std::vector<size_t>& which, const Progress& progress, size_t& done, size_t total);

    // What a capture of one face adds to `fg` (capture.cpp): the renderer's passes at the face's
    // camera and probes.capture_bounce; `face` is the lit face with the bounce.
    struct CaptureFace {
        render::FrameInputs frame;
        render::GBuffer g;
        TextureHandle face;
        TextureHandle ground;  // the planar grounds as imported (probes.capture_bounce reads them)
        TextureHandle distances;  // the probes' distance cubes as imported (read there too)
    };
    // `directSpecular` false: the lighting leaves the lights' highlights out (a local probe's faces).
    CaptureFace addCaptureFace(FrameGraph& fg, glm::vec3 center, uint32_t face, uint32_t res, bool directSpecular = true);
    // The same for any camera (a planar probe's mirrored view): `frame` at frame.camera's size.
    // `deep`: its surfaces are one reflection deep, so they reflect `below` where there is one.
    CaptureFace addCaptureView(FrameGraph& fg, const render::FrameInputs& frame, bool deep = false);
    // With planar probes and probes.bounces >= 2, makes `below` (probes.cpp).
    void allocateBelow();
    // Copies probe `index`'s cube of `cubes` into `below`.
    void keepBelow(size_t index);
    // probes.distance_store after face `face` of probe `index` (res its resolution) in `c`.
    void addDistanceStore(FrameGraph& fg, const CaptureFace& c, size_t index, uint32_t face, uint32_t res);
    // Compiles and runs a capture graph; returns its GPU milliseconds.
    double runCapture(FrameGraph& fg);

    // CMOs (cmo.cpp).
    void createCmos();
    void validateCmos() const;
    void captureCmoFace(size_t index, uint32_t face);
    // Box mips of the radiance and the min/max hierarchy of CMO `index`, then its record.
    void finishCmo(size_t index);
    uint32_t writeCmoRecords();
    void updateCmos(const Progress& progress);
    // Planar probes (planar.cpp).
    void createPlanar();
    void validatePlanar() const;
    void allocatePlanar(uint32_t width, uint32_t height);
    // Into its layer's mip `base`, the crop's texels at `rect` (renderPlanar).
    void renderPlanarProbe(size_t index, const render::FrameInputs& view, uint32_t base, const TexelRect& rect);
    // The grounds' array, records and pipeline (planar.cpp); renderGrounds renders every planar
    // probe's ground and writes their records.
    void createGrounds();
    void renderGrounds();
    // One step of the first probe or CMO whose capture cycle is under way (moveProbe, recapture).
    void stepRelocations();
};

}  // namespace speculum::probes
