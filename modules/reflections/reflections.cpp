// The module's entry point: resources that live across frames, the per-frame uniforms, and the
// order of the passes (passes.cpp records them).
#include "module_impl.hpp"

#include "speculum/core.hpp"
#include "speculum/reflections/math.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string_view>

namespace speculum::reflections {
namespace {

constexpr VkShaderStageFlags kCompute = VK_SHADER_STAGE_COMPUTE_BIT;

// Per material: mode and CMO tracing, roughness scale, roughness override (-1: none), max screen-space
// roughness. Every lit material reflects (reflectionsOf), glTF's default material included.
std::vector<glm::vec4> materialTable(const Scene& scene) {
    std::vector<glm::vec4> table;
    auto row = [&](const Material& m) {
        const MaterialReflections r = reflectionsOf(m);
        // x: the mode in bits 0-1, bit 2 CMO tracing (material.glsl); local_cubemap_only skips CMOs.
        bool cmos = r.traceCmos && r.mode != ReflectionMode::LocalCubemapOnly;
        table.emplace_back(float(uint32_t(r.mode) | (cmos ? 4u : 0u)), r.roughnessScale,
                           r.roughnessOverride.value_or(-1.0f), r.maxScreenSpaceRoughness);
    };
    for (const Material& m : scene.materials) row(m);
    row(Material{});
    table.resize(std::min<size_t>(table.size(), render::kMaxIndexedMaterials + 1));
    return table;
}

}  // namespace

Reflections::Impl::Impl(const gpu::Context& c, render::Renderer& r)
    : ctx(c),
      renderer(r),
      hiz(gpu::createComputePipeline(c, "reflections/hiz.comp", sizeof(uint32_t), "reflections.hiz")),
      hizFirst(gpu::createComputePipeline(c, "reflections/hiz_first.comp", 0, "reflections.hiz")),
      visibility(
          gpu::createComputePipeline(c, "reflections/visibility.comp", sizeof(uint32_t), "reflections.visibility")),
      colorDown(gpu::createComputePipeline(c, "reflections/color_down.comp", 0, "reflections.color_pyramid")),
      hizView(gpu::createComputePipeline(c, "reflections/hiz_view.comp", 0, "reflections.hiz_view")),
      temporal(gpu::createComputePipeline(c, "reflections/temporal.comp", 0, "reflections.temporal")),
      refresh(gpu::createComputePipeline(c, "reflections/refresh.comp", 0, "reflections.refresh")),
      upsampler(c),
      nearest(gpu::createSampler(c, VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, false)),
      trilinear(gpu::createSampler(c, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, true)),
      uniforms(c, sizeof(FrameUniforms), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true,
               "reflections.frame") {
    std::vector<glm::vec4> table = materialTable(r.scene());
    materialCount = uint32_t(table.size());
    materials = gpu::uploadBuffer(c, std::as_bytes(std::span(table)), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                  "reflections.materials");
    noProbeCubes = gpu::Image(
        c,
        {4, 4, VK_FORMAT_R16G16B16A16_SFLOAT, 1, 6, true, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT},
        "reflections.no_probes");
    noProbeRecords = gpu::Buffer(c, sizeof(probes::shader::Probe), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true,
                                 "reflections.no_probe_records");
    std::memset(noProbeRecords.mapped(), 0, sizeof(probes::shader::Probe));
    noPlanarImages = gpu::Image(
        c, {4, 4, VK_FORMAT_R16G16B16A16_SFLOAT, 1, 1, false, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT},
        "reflections.no_planar");
    noPlanarRecords = gpu::Buffer(c, sizeof(probes::shader::PlanarProbe), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true,
                                  "reflections.no_planar_records");
    std::memset(noPlanarRecords.mapped(), 0, sizeof(probes::shader::PlanarProbe));
    c.submitAndWait([&](VkCommandBuffer cmd) {
        for (VkImage image : {noProbeCubes.get(), noPlanarImages.get()}) {
            gpu::transition(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                            VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
            VkClearColorValue black{};
            VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, VK_REMAINING_ARRAY_LAYERS};
            vkCmdClearColorImage(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &black, 1, &all);
            gpu::transition(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                            VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        }
    });
}

probes::ProbeSet Reflections::Impl::importNoProbes(FrameGraph& g) const {
    probes::ProbeSet set;
    set.cubes =
        g.importTexture("reflections.no_probes",
                        {.width = 4, .height = 4, .format = VK_FORMAT_R16G16B16A16_SFLOAT, .layers = 6, .cube = true},
                        {noProbeCubes.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, noProbeCubes.desc().usage});
    // Never read (count 0): the same black cube under its own name.
    set.distances =
        g.importTexture("reflections.no_probe_distances",
                        {.width = 4, .height = 4, .format = VK_FORMAT_R16G16B16A16_SFLOAT, .layers = 6, .cube = true},
                        {noProbeCubes.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, noProbeCubes.desc().usage});
    set.records = g.importBuffer("reflections.no_probe_records", {sizeof(probes::shader::Probe)}, {noProbeRecords.get()});
    set.planar = importNoPlanar(g);
    return set;
}

probes::PlanarSet Reflections::Impl::importNoPlanar(FrameGraph& g) const {
    probes::PlanarSet set;
    set.images = g.importTexture("reflections.no_planar", {.width = 4, .height = 4, .format = VK_FORMAT_R16G16B16A16_SFLOAT},
                                 {noPlanarImages.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, noPlanarImages.desc().usage});
    set.records = g.importBuffer("reflections.no_planar_records", {sizeof(probes::shader::PlanarProbe)},
                                 {noPlanarRecords.get()});
    // No grounds either (count 0): the same dummies stand in for their bindings.
    static_assert(sizeof(probes::shader::PlanarGround) <= sizeof(probes::shader::PlanarProbe));
    set.ground = set.images;
    set.groundRecords = set.records;
    return set;
}

void Reflections::Impl::writeUniforms(const ReflectionInputs& in, const ReflectionSettings& s,
                                      const ReflectionSettings& asked, uint32_t w, uint32_t h, uint32_t levels) {
    const render::CameraState& cam = in.frame.camera;
    FrameUniforms u{};
    u.viewProj = cam.viewProj;
    u.invViewProj = cam.invViewProj;
    u.prevViewProj = in.frame.previousCamera.viewProj;
    u.view = cam.view;
    u.eye = cam.position;
    u.znear = cam.znear;
    u.size = glm::vec4(float(w), float(h), 1.0f / float(w), 1.0f / float(h));
    u.maxIterations = float(s.maxIterations);
    u.linearPreSteps = float(s.linearPreSteps);
    u.hizStartLevel = float(s.hizStartLevel);
    u.hizStopLevel = float(s.hizStopLevel);
    u.thickness = s.thickness;
    u.linearStride = s.linearStride;
    u.linearMaxSteps = float(s.linearMaxSteps);
    u.refineSteps = float(s.refineSteps);
    u.coneSamples = float(s.coneSamples);
    // Screen space off: a limit below every roughness, so nothing is traced and coverage is 0.
    u.maxRoughness = s.screenSpace ? s.maxRoughness : -1.0f;
    u.envMaxMip = float(renderer.environment().mipCount() - 1);
    // Radians per pixel at the image centre: a sphere of r pixels at view distance z has a
    // world radius of about r * z * pixelAngle.
    u.pixelAngle = 2.0f * std::tan(cam.yfov * 0.5f) / float(h);
    u.edgeFade = s.edgeFade;
    u.cameraFadeStart = s.cameraFadeStart;
    u.cameraFadeEnd = s.cameraFadeEnd;
    u.distanceFadeStart = s.distanceFadeStart;
    u.distanceFadeEnd = s.distanceFadeEnd;
    u.debugHizMip = float(s.debugHizMip);
    u.invExposure = 1.0f / std::max(renderer.options().exposure, 1e-6f);
    u.traceScale = s.resolution == Resolution::Half ? 2.0f : 1.0f;
    u.temporalAlpha = s.temporalAlpha;
    u.temporalClip = s.temporalClip;
    u.frameIndex = frameIndex;
    // Accumulation starts once the colour pyramid's reflections of reflections have filled:
    // after a reset the bounce loop gains a bounce a frame (a mirror seen in a mirror is black,
    // then bright), and accumulating those first frames lags every pixel that reflects a
    // reflection by the accumulation's time constant (16 frames were not enough to reach the
    // un-accumulated image, tests/stability converge). Three frames hold three bounces.
    framesSinceReset = history.valid() ? framesSinceReset + 1 : 0;
    bool bouncesFilled = !s.multiBounce || framesSinceReset >= kBounceFillFrames;
    // A camera cut: hosts call resetHistory(); a turn of more than 45 degrees in one frame is
    // taken as one too (its history would be rejected almost everywhere anyway, and what passes
    // the checks by chance is another view's).
    const glm::vec3 forward = -glm::vec3(glm::transpose(cam.view)[2]);
    const glm::vec3 previousForward = -glm::vec3(glm::transpose(in.frame.previousCamera.view)[2]);
    bool cut = glm::dot(forward, previousForward) < std::cos(glm::radians(45.0f));
    u.temporalValid = history.temporalValid() && lastSettings && *lastSettings == asked && bouncesFilled && !cut ? 1u : 0u;
    u.traceMode = uint32_t(s.trace);
    u.coverageMode = uint32_t(s.coverage);
    u.historyValid = history.valid() ? 1u : 0u;
    u.hizLevels = levels;
    u.debugView = uint32_t(s.debugView);
    u.multiBounce = s.multiBounce ? 1u : 0u;
    u.hitReflectMaxRoughness = s.hitReflectMaxRoughness;
    u.materialCount = materialCount;
    u.probeCount = s.probes && in.probes.cubes.valid() ? in.probes.count : 0u;
    u.cmoCount = s.cmos && in.probes.cmos.records.valid() ? in.probes.cmos.count : 0u;
    u.cmoMaxIterations = float(s.cmoMaxIterations);
    u.cmoLinearStep = s.cmoLinearStep;
    u.cmoThickness = s.cmoThickness;
    u.cmoMaxDistance = s.cmoMaxDistance;
    u.cmoBounces = float(s.cmoBounces);
    u.cmoMaxRoughness = s.cmoMaxRoughness;
    u.cmoPassBehind = s.cmoPassBehind ? 1u : 0u;
    u.planarCount = s.probes && in.probes.planar.records.valid() ? in.probes.planar.count : 0u;
    u.groundCount = s.probes && in.probes.planar.groundRecords.valid() ? in.probes.planar.groundCount : 0u;
    u.refreshValid = history.refreshValid() && lastSettings && *lastSettings == asked && !cut ? 1u : 0u;
    // Moved beyond rounding: a camera path interpolating between two equal keys (glm::mix) gives
    // matrices an ulp apart, and clipping a still camera's history stops ray_budget=quarter from
    // reaching the full-rate image (tests/stability, ray_budget).
    float largest = 0.0f, change = 0.0f;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            largest = std::max(largest, std::abs(cam.viewProj[c][r]));
            change = std::max(change, std::abs(cam.viewProj[c][r] - in.frame.previousCamera.viewProj[c][r]));
        }
    u.cameraMoved = change > 1e-5f * largest ? 1u : 0u;
    std::memcpy(uniforms.mapped(), &u, sizeof(u));
}

void Reflections::Impl::ensureHistory(uint32_t w, uint32_t h, bool refreshImages) {
    constexpr VkImageUsageFlags kRefreshUsage =
        VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    if (refreshImages && (history.refresh.desc().width != w || history.refresh.desc().height != h)) {
        history.refresh = gpu::HistoryImages(ctx, {w, h, VK_FORMAT_R16G16B16A16_SFLOAT, 1, 1, false, kRefreshUsage},
                                             "reflections.history.refresh");
        history.refreshNormal = gpu::HistoryImages(
            ctx, {w, h, VK_FORMAT_R16G16B16A16_SFLOAT, 1, 1, false, kRefreshUsage}, "reflections.history.refresh_normal");
    }
    if (history.width == w && history.height == h) return;
    // Storage: the passes write them (composite, Hi-Z, temporal); transfer source: the AOVs
    // (linear, hiz, reflection) read them back, and the lit copies read the colour.
    constexpr VkImageUsageFlags kStorageUsage =
        VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    history.color = gpu::HistoryImages(ctx, {w, h, render::kLinearFormat, 1, 1, false, kStorageUsage},
                                       "reflections.history.color");
    history.hiz =
        gpu::HistoryImages(ctx, {w, h, kHiZFormat, pyramidLevels(w, h), 1, false, kStorageUsage}, "reflections.hiz");
    history.reflection = gpu::HistoryImages(ctx, {w, h, VK_FORMAT_R16G16B16A16_SFLOAT, 1, 1, false, kStorageUsage},
                                            "reflections.history.reflection");
    history.normal = gpu::HistoryImages(ctx, {w, h, VK_FORMAT_R16G16B16A16_SFLOAT, 1, 1, false, kStorageUsage},
                                        "reflections.history.normal");
    history.width = w;
    history.height = h;
}

gpu::DescriptorWriter Reflections::Impl::writer() const {
    gpu::DescriptorWriter w;
    // One buffer, read twice: as the storage buffer `rf` and its leading matrices as the uniform
    // block `rfm` (modules/reflections/shaders/frame.h says why).
    w.buffer("rf", uniforms.get()).buffer("rfm", uniforms.get());
    return w;
}

gpu::DescriptorWriter Reflections::Impl::surfaceWriter(PassContext& pc, TextureHandle hizImage, TextureHandle normal,
                                                       TextureHandle emissive) const {
    gpu::DescriptorWriter w = writer();
    w.sampled("hiz", pc.view(hizImage), nearest)
        .sampled("normalTex", pc.view(normal), nearest)
        .sampled("emissiveTex", pc.view(emissive), nearest)
        .buffer("MaterialTable", materials.get());
    return w;
}

void Reflections::Impl::dispatch(PassContext& pc, const gpu::Pipeline& p, gpu::DescriptorWriter& w, VkExtent2D extent,
                                 const void* push, uint32_t pushBytes) const {
    p.bind(pc.cmd());
    w.push(ctx, pc.cmd(), p);
    if (push) vkCmdPushConstants(pc.cmd(), p.layout(), kCompute, 0, pushBytes, push);
    vkCmdDispatch(pc.cmd(), (extent.width + 7) / 8, (extent.height + 7) / 8, 1);
}

Reflections::Reflections(const gpu::Context& ctx, render::Renderer& renderer)
    : impl_(std::make_unique<Impl>(ctx, renderer)) {}

Reflections::~Reflections() = default;

void Reflections::resetHistory() {
    impl_->history.invalidate();
}

namespace {
// Specialization constants with the tile mode at id 310 (tiles.glsl), above every other id.
std::vector<uint32_t> withTileMode(std::vector<uint32_t> constants, uint32_t tileMode) {
    constants.resize(311, 0u);
    constants[310] = tileMode;
    return constants;
}
}  // namespace

const gpu::Pipeline& Reflections::Impl::trace(TraceMode mode, Resolution resolution, GlossyMode glossy,
                                              uint32_t tileMode) {
    std::optional<gpu::Pipeline>& p =
        traces.at((size_t(mode) * 4 + size_t(resolution) * 2 + size_t(glossy)) * kTileModes + tileMode);
    if (!p)
        p = gpu::createComputePipeline(ctx, "reflections/trace.comp", 0, "reflections.trace",
                                       withTileMode({uint32_t(mode), uint32_t(resolution), uint32_t(glossy)}, tileMode));
    return *p;
}

const gpu::Pipeline& Reflections::Impl::resolve(Resolution resolution, GlossyMode glossy, uint32_t tileMode) {
    std::optional<gpu::Pipeline>& p = resolves.at((size_t(resolution) * 2 + size_t(glossy)) * kTileModes + tileMode);
    if (!p) {
        // The scene's lights (ids 0-287: mirror hits move their highlights), then ids 300 and 301.
        std::vector<uint32_t> constants = renderer.lightingConstants();
        constants.resize(302, 0u);
        constants[300] = uint32_t(resolution);
        constants[301] = uint32_t(glossy);
        p = gpu::createComputePipeline(ctx, "reflections/resolve.comp", 0, "reflections.resolve",
                                       withTileMode(std::move(constants), tileMode));
    }
    return *p;
}

const gpu::Pipeline& Reflections::Impl::cmoTrace(Resolution resolution, bool linear, uint32_t tileMode) {
    std::optional<gpu::Pipeline>& p = cmoTraces.at((size_t(resolution) * 2 + (linear ? 1 : 0)) * kTileModes + tileMode);
    if (!p) {
        // The scene's lights (ids 0-287, shaders/engine/scene_lights.glsl), then ids 300 and 301.
        std::vector<uint32_t> constants = renderer.lightingConstants();
        constants.resize(302, 0u);
        constants[300] = uint32_t(resolution);
        constants[301] = linear ? 1u : 0u;
        p = gpu::createComputePipeline(ctx, "reflections/cmo_trace.comp", 0, "reflections.cmo_trace",
                                       withTileMode(std::move(constants), tileMode));
    }
    return *p;
}

const gpu::Pipeline& Reflections::Impl::classify(Resolution resolution, RayBudget budget) {
    std::optional<gpu::Pipeline>& p = classifies.at(size_t(resolution) * 2 + size_t(budget));
    if (!p)
        p = gpu::createComputePipeline(ctx, "reflections/classify.comp", 0, "reflections.classify",
                                       {0u, uint32_t(resolution), uint32_t(budget)});
    return *p;
}

void Reflections::Impl::dispatchTiles(PassContext& pc, const gpu::DescriptorWriter& w, BufferHandle tiles, bool tiled,
                                      std::initializer_list<TileRun> runs, VkExtent2D extent,
                                      BufferHandle footprint) const {
    for (const TileRun& run : runs) {
        gpu::DescriptorWriter copy = w;  // push() clears its writer
        run.pipeline->bind(pc.cmd());
        copy.push(ctx, pc.cmd(), *run.pipeline);
        if (!tiled) {
            vkCmdDispatch(pc.cmd(), (extent.width + 7) / 8, (extent.height + 7) / 8, 1);
            return;
        }
        if (footprint.valid()) {
            // The footprint's dispatches, in kFootprintLists' order.
            const VkDeviceSize slot =
                std::find(kFootprintLists.begin(), kFootprintLists.end(), run.list) - kFootprintLists.begin();
            vkCmdDispatchIndirect(pc.cmd(), pc.buffer(footprint), slot * sizeof(glm::uvec4));
            continue;
        }
        vkCmdDispatchIndirect(pc.cmd(), pc.buffer(tiles), VkDeviceSize(run.list) * sizeof(glm::uvec4));
    }
}

const gpu::Pipeline& Reflections::Impl::reproject(uint32_t tileMode, bool half, uint32_t list) {
    const uint32_t key = (tileMode * 2 + (half ? 1 : 0)) * shader::kTileLists + list;
    auto it = reprojects.find(key);
    if (it == reprojects.end())
        it = reprojects
                 .emplace(key, gpu::createComputePipeline(ctx, "reflections/reproject.comp", 0, "reflections.reproject",
                                                          withTileMode({0u, 0u, half ? 2u : 1u, list}, tileMode)))
                 .first;
    return it->second;
}

const gpu::Pipeline& Reflections::Impl::lookupFull(uint32_t tileMode, uint32_t list) {
    const uint32_t key = tileMode * shader::kTileLists + list;
    auto it = lookupFulls.find(key);
    if (it == lookupFulls.end())
        it = lookupFulls
                 .emplace(key, gpu::createComputePipeline(ctx, "reflections/lookup_full.comp", 0, "reflections.lookup_full",
                                                          withTileMode({0u, 0u, 2u, list}, tileMode)))
                 .first;
    return it->second;
}

const gpu::Pipeline& Reflections::Impl::hitReuse(uint32_t tileMode, bool cmos, bool linear, uint32_t list) {
    const uint32_t key = ((tileMode * 2 + (cmos ? 1 : 0)) * 2 + (linear ? 1 : 0)) * shader::kTileLists + list;
    auto it = hitReuses.find(key);
    if (it == hitReuses.end()) {
        // The CMO variant shades hits as the CMO trace does: the scene's lights (ids 0-287).
        std::vector<uint32_t> constants = cmos ? renderer.lightingConstants() : std::vector<uint32_t>{};
        constants.resize(304, 0u);
        constants[301] = linear ? 1u : 0u;
        constants[302] = 2u;  // the footprint's scale
        constants[303] = list;
        it = hitReuses
                 .emplace(key, gpu::createComputePipeline(
                                   ctx, cmos ? "reflections/hit_reuse_cmo.comp" : "reflections/hit_reuse.comp", 0,
                                   "reflections.hit_reuse", withTileMode(std::move(constants), tileMode)))
                 .first;
    }
    return it->second;
}

const gpu::Pipeline& Reflections::Impl::composite(const CompositeVariant& v, uint32_t list) {
    const uint32_t key =
        ((uint32_t(v.view) * 8 + (v.temporal ? 4 : 0) + (v.tiled ? 2 : 0) + (v.half ? 1 : 0)) * shader::kTileLists) + list;
    auto it = composites.find(key);
    if (it == composites.end()) {
        using namespace shader;
        std::vector<uint32_t> constants{uint32_t(v.view), v.temporal ? 1u : 0u, v.half ? 2u : 1u, list};
        it = composites
                 .emplace(key, gpu::createComputePipeline(
                                   ctx, "reflections/composite.comp", 0, "reflections.composite",
                                   withTileMode(std::move(constants), v.tiled ? kTileModeWork : kTileModeScreen)))
                 .first;
    }
    return it->second;
}

ReflectionOutputs Reflections::addPasses(FrameGraph& graph, const ReflectionInputs& given,
                                         const ReflectionSettings& asked, bool hizView) {
    Impl& m = *impl_;
    // A quarter ray budget traces on the half-size grid: `s` is what the passes run with, `asked`
    // what a change of resets the history.
    const bool quarter = asked.rayBudget == RayBudget::Quarter;
    ReflectionSettings s = asked;
    if (quarter) s.resolution = Resolution::Half;
    // Without probes (or planar probes) from the host, the passes bind the dummies, imported once.
    ReflectionInputs in = given;
    if (!in.probes.cubes.valid()) {
        probes::CmoSet cmos = in.probes.cmos;
        in.probes = m.importNoProbes(graph);
        in.probes.cmos = cmos;
    } else if (!in.probes.planar.images.valid()) {
        in.probes.planar = m.importNoPlanar(graph);
    }
    uint32_t w = graph.config().outputWidth, h = graph.config().outputHeight;
    uint32_t levels = pyramidLevels(w, h);
    m.ensureHistory(w, h, quarter);
    m.writeUniforms(in, s, asked, w, h, levels);

    ReflectionOutputs out;
    TextureHandle visibility1;
    out.hiz = m.addHiZ(graph, in.gbuffer.depth, levels, visibility1);
    out.visibility = m.addVisibility(graph, out.hiz, visibility1, levels);
    Impl::Classified tiles = m.addClassify(graph, in, out.hiz, s);
    out.colorPyramid = m.addColorPyramid(graph, in, out.visibility, levels, tiles, s);
    TextureHandle guide = out.guide = tiles.guide;
    out.hit = m.addTrace(graph, in, out.hiz, tiles, s);
    if (s.cmos && in.probes.cmos.records.valid() && in.probes.cmos.count > 0) m.addCmoTrace(graph, in, tiles, s, out);
    m.addResolve(graph, in, tiles, s, out);
    const TextureHandle halfReflection = out.reflection;
    if (guide.valid()) {
        const render::CameraState& cam = in.frame.camera;
        UpsampleInputs up{in.gbuffer.depth, in.gbuffer.normal, guide, out.reflection, cam.invViewProj, cam.position};
        // A quarter budget's refresh upsamples the reflection itself, where it needs to.
        out.reflection = quarter ? m.addRefresh(graph, in, out.hiz, out, halfReflection)
                                 : m.upsampler.addPass(graph, up, "reflections.upsample", "reflections.reflection");
        if (!quarter && s.fullResLookups)
            out.reflection = m.addLookupFull(graph, in, tiles, s, out.hiz, out.method, out.reflection);
        if (!quarter && s.hitReuse && s.screenSpace)
            out.reflection = m.addHitReuse(graph, in, tiles, s, out, out.method, halfReflection, out.reflection);
        // Culled unless the method AOV or a debug view reads it.
        up.low = out.method;
        out.method = m.upsampler.addPass(graph, up, "reflections.upsample_method", "reflections.method");
    }
    TextureHandle raw = out.reflection;
    if (s.temporal) out.reflection = m.addTemporal(graph, in, out.hiz, out.reflection, out.distance);
    out.lit = m.addComposite(graph, in, out, tiles, s, s.temporal ? raw : TextureHandle{});
    if (hizView) out.hizView = m.addHiZView(graph, out.hiz);
    m.lastSettings = asked;
    ++m.frameIndex;
    return out;
}

}  // namespace speculum::reflections
