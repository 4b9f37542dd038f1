// Capturing a probe: one frame graph per face at the probe's resolution with the renderer's own
// passes (depth prepass, shadows, G-buffer, lighting), then probes.capture_bounce (the specular
// ambient of reflective surfaces from the previous bake, then the sky) and probes.store (the face
// into the probe's radiance cube, flipped vertically: see faceCamera). After the sixth face the
// radiance cube's box chain and the sky's GGX prefilter write the probe's cube of the array.
#include "module_impl.hpp"

#include "speculum/core.hpp"

#include <chrono>

namespace speculum::probes {
namespace {

struct BouncePush {
    glm::mat4 invViewProj;
    glm::vec4 eye;
    glm::uvec4 info;
};
static_assert(sizeof(BouncePush) == 96);

}  // namespace

Probes::Impl::CaptureFace Probes::Impl::addCaptureFace(FrameGraph& fg, glm::vec3 center, uint32_t face, uint32_t res,
                                                      bool directSpecular) {
    render::FrameInputs frame;
    frame.camera = frame.previousCamera = faceCamera(center, face, res);
    frame.directSpecular = directSpecular;
    return addCaptureView(fg, frame);
}

Probes::Impl::CaptureFace Probes::Impl::addCaptureView(FrameGraph& fg, const render::FrameInputs& view, bool deep) {
    CaptureFace c;
    c.frame = view;
    const uint32_t width = view.camera.width, height = view.camera.height;
    c.g = renderer.addGBufferPasses(fg, c.frame);
    // The capture composites the specular ambient of reflective pixels itself (capture_bounce).
    TextureHandle lit = renderer.addLightingPass(fg, c.frame, c.g, {.moduleSpecular = true});
    const bool fromBelow = deep && below.get() != VK_NULL_HANDLE;
    const gpu::Image& source = fromBelow ? below : cubes;
    const VkImageLayout layout = fromBelow ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    TextureHandle array = fg.importTexture(fromBelow ? "probes.cubes_below" : "probes.cubes", descOf(source),
                                           {source.get(), layout, layout, source.desc().usage});
    BufferHandle recs = fg.importBuffer("probes.records", {records.size()}, {records.get()});
    const PlanarState& pl = planar;
    c.ground = fg.importTexture("probes.planar_ground", descOf(pl.ground),
                                {pl.ground.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                                 pl.ground.desc().usage});
    BufferHandle groundRecs = fg.importBuffer("probes.ground_records", {pl.groundRecords.size()},
                                              {pl.groundRecords.get()});
    c.distances = fg.importTexture("probes.distances", descOf(distances),
                                   {distances.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                                    distances.desc().usage});
    struct Bounce {
        render::GBuffer g;
        TextureHandle lit, array, ground, distances, out;
        BufferHandle recs, groundRecs;
    };
    const uint32_t visible = readyCount();
    const render::Environment& env = renderer.environment();
    const render::FrameInputs frame = c.frame;
    const render::GBuffer& g = c.g;
    const auto& b = fg.addPass<Bounce>(
        "probes.capture_bounce", PassType::Compute,
        [&](PassBuilder& pb, Bounce& d) {
            d.g = render::readSurfaceAttachments(pb, g);
            d.lit = pb.read(lit, TextureUsage::Sampled);
            d.array = pb.read(array, TextureUsage::Sampled);
            d.recs = pb.read(recs, BufferUsage::StorageRead);
            d.ground = pb.read(c.ground, TextureUsage::Sampled);
            d.distances = pb.read(c.distances, TextureUsage::Sampled);
            d.groundRecs = pb.read(groundRecs, BufferUsage::StorageRead);
            d.out = pb.write(pb.create("probes.face", {.format = render::kLinearFormat}), TextureUsage::StorageWrite);
        },
        [this, frame, visible, width, height, &env, grounds = pl.groundCount](const Bounce& d, PassContext& pc) {
            bounce.bind(pc.cmd());
            gpu::DescriptorWriter()
                .sampled("depthTex", pc.view(d.g.depth), nearest)
                .sampled("albedoTex", pc.view(d.g.albedo), nearest)
                .sampled("normalTex", pc.view(d.g.normal), nearest)
                .sampled("emissiveTex", pc.view(d.g.emissive), nearest)
                .sampled("litTex", pc.view(d.lit), nearest)
                .sampled("dfgTex", env.dfg().view(), env.sampler())
                .buffer("ProbeBuffer", pc.buffer(d.recs))
                .sampled("probeCubes", pc.view(d.array, {}, VK_IMAGE_VIEW_TYPE_CUBE_ARRAY), sampler)
                .sampled("probeDistance", pc.view(d.distances, {}, VK_IMAGE_VIEW_TYPE_CUBE_ARRAY), nearest)
                .sampled("envSpecular", env.specular().view(), env.sampler())
                .storage("outLit", pc.view(d.out))
                .buffer("GroundBuffer", pc.buffer(d.groundRecs))
                .sampled("groundImages", pc.view(d.ground, {}, VK_IMAGE_VIEW_TYPE_2D_ARRAY), sampler)
                .push(ctx, pc.cmd(), bounce);
            BouncePush p{frame.camera.invViewProj, glm::vec4(frame.camera.position, float(env.mipCount() - 1)),
                         glm::uvec4(width, height, visible, grounds)};
            vkCmdPushConstants(pc.cmd(), bounce.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(p), &p);
            vkCmdDispatch(pc.cmd(), (width + 7) / 8, (height + 7) / 8, 1);
        });
    c.face = b.out;
    return c;
}

void Probes::Impl::addDistanceStore(FrameGraph& fg, const CaptureFace& c, size_t index, uint32_t face, uint32_t res) {
    TextureHandle target = c.distances;
    struct Store {
        TextureHandle depth, normal, albedo, emissive, out;
    };
    const auto camera = c.frame.camera;
    const auto& s = fg.addPass<Store>(
        "probes.distance_store", PassType::Compute,
        [&](PassBuilder& pb, Store& d) {
            d.depth = pb.read(c.g.depth, TextureUsage::Sampled);
            d.normal = pb.read(c.g.normal, TextureUsage::Sampled);
            d.albedo = pb.read(c.g.albedo, TextureUsage::Sampled);
            d.emissive = pb.read(c.g.emissive, TextureUsage::Sampled);
            d.out = pb.write(target, TextureUsage::StorageWrite);
        },
        [this, camera, index, face, res](const Store& d, PassContext& pc) {
            distanceStore.bind(pc.cmd());
            gpu::DescriptorWriter()
                .sampled("depthTex", pc.view(d.depth), nearest)
                .sampled("normalTex", pc.view(d.normal), nearest)
                .sampled("albedoTex", pc.view(d.albedo), nearest)
                .sampled("emissiveTex", pc.view(d.emissive), nearest)
                .storage("outDistance", pc.view(d.out, {}, VK_IMAGE_VIEW_TYPE_2D_ARRAY))
                .push(ctx, pc.cmd(), distanceStore);
            BouncePush p{camera.invViewProj, glm::vec4(camera.position, 0.0f),
                         glm::uvec4(res, faceSize, face, uint32_t(6 * index))};
            vkCmdPushConstants(pc.cmd(), distanceStore.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(p), &p);
            vkCmdDispatch(pc.cmd(), (faceSize + 7) / 8, (faceSize + 7) / 8, 1);
        });
    fg.markOutput(s.out);
}

double Probes::Impl::runCapture(FrameGraph& fg) {
    fg.compile(allocator);
    ctx.submitAndWait([&](VkCommandBuffer cmd) { fg.execute(executor, cmd); });
    double total = 0.0;
    for (const auto& t : executor.readTimings()) total += t.ms;
    return total;
}

void Probes::Impl::captureFace(size_t index, uint32_t face) {
    const ProbeInfo& info = probes[index];
    const uint32_t res = info.probe.resolution;
    FrameGraph fg(FrameGraphConfig{res, res});
    // Without the direct lights' specular (FrameInputs::directSpecular says why); a CMO's faces
    // keep it, since its trace moves those terms to each ray's direction (relight.glsl).
    CaptureFace c = addCaptureFace(fg, glm::vec3(info.gpu.center), face, res, false);
    const gpu::Image& target = radiance[index];
    TextureHandle cube = fg.importTexture("probes.radiance", descOf(target),
                                          {target.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                                           target.desc().usage});
    struct Store {
        TextureHandle face, cube;
    };
    const auto& s = fg.addPass<Store>(
        "probes.store", PassType::Transfer,
        [&](PassBuilder& pb, Store& d) {
            d.face = pb.read(c.face, TextureUsage::TransferSrc);
            d.cube = pb.write(cube, TextureUsage::TransferDst, Subresource{0, 1, face, 1});
        },
        [face, res](const Store& d, PassContext& pc) {
            VkImageBlit blit{};
            blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            blit.srcOffsets[0] = {0, 0, 0};
            blit.srcOffsets[1] = {int32_t(res), int32_t(res), 1};
            blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, face, 1};
            // Rows reversed: the camera's rows run against the face's t axis (faceCamera).
            blit.dstOffsets[0] = {0, int32_t(res), 0};
            blit.dstOffsets[1] = {int32_t(res), 0, 1};
            vkCmdBlitImage(pc.cmd(), pc.image(d.face), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pc.image(d.cube),
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_NEAREST);
        });
    fg.markOutput(s.cube);
    addDistanceStore(fg, c, index, face, res);
    ms += runCapture(fg);
    ++faces;
}

void Probes::Impl::prefilter(size_t index, const std::vector<render::PrefilterStep>& plan, size_t step) {
    const gpu::Image& source = radiance[index];
    auto start = std::chrono::steady_clock::now();
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        if (step == 0) filter.recordBoxChain(cmd, source, sampler);
        else
            gpu::transition(cmd, source.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL,
                            VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        gpu::transition(cmd, cubes.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                        VK_IMAGE_LAYOUT_GENERAL, 0, VK_REMAINING_MIP_LEVELS, uint32_t(6 * index), 6);
        // The slices of one step write disjoint texels and only read the source: no barrier between.
        for (const render::PrefilterSlice& slice : plan[step])
            filter.recordPrefilterSlice(cmd, source, sampler, targetViews[index][slice.mip].get(), faceSize, mips,
                                        slice, uint32_t(settings.prefilterSamples));
        gpu::transition(cmd, cubes.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL,
                        VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, 0, VK_REMAINING_MIP_LEVELS, uint32_t(6 * index), 6);
        gpu::transition(cmd, source.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                        VK_IMAGE_LAYOUT_GENERAL);
    });
    ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (step + 1 < plan.size()) return;
    ready[index] = true;
    keepBelow(index);
    writeRecords();
}

bool Probes::Impl::cycleStep(size_t index, size_t step) {
    if (step < 6) captureFace(index, uint32_t(step));
    else prefilter(index, steps, step - 6);
    return step + 1 == timeSlicedCycle();
}

}  // namespace speculum::probes

namespace speculum::probes {

TextureHandle Probes::addDebugView(FrameGraph& graph, const render::GBuffer& gbuffer, const render::FrameInputs& frame,
                                   const ProbeSet& set, DebugView view) {
    Impl& m = *impl_;
    std::optional<gpu::Pipeline>& pipeline = m.debug[size_t(view)];
    if (!pipeline) {
        pipeline = gpu::createComputePipeline(m.ctx, "probes/debug.comp", sizeof(BouncePush), "probes.debug",
                                              {uint32_t(view)});
    }
    struct Data {
        TextureHandle depth, normal, cubes, out;
        BufferHandle records;
    };
    const float invExposure = 1.0f / std::max(m.renderer.options().exposure, 1e-6f);
    const gpu::Pipeline* p = &*pipeline;
    const auto& d = graph.addPass<Data>(
        "probes.debug", PassType::Compute,
        [&](PassBuilder& b, Data& data) {
            data.depth = b.read(gbuffer.depth, TextureUsage::Sampled);
            data.normal = b.read(gbuffer.normal, TextureUsage::Sampled);
            data.cubes = b.read(set.cubes, TextureUsage::Sampled);
            data.records = b.read(set.records, BufferUsage::StorageRead);
            data.out = b.write(b.create("probes.debug", {.format = render::kLinearFormat}), TextureUsage::StorageWrite);
        },
        [&m, p, frame, count = set.count, invExposure](const Data& data, PassContext& pc) {
            VkExtent2D e = pc.extent(data.out);
            p->bind(pc.cmd());
            gpu::DescriptorWriter()
                .sampled("depthTex", pc.view(data.depth), m.nearest)
                .sampled("normalTex", pc.view(data.normal), m.nearest)
                .buffer("ProbeBuffer", pc.buffer(data.records))
                .sampled("probeCubes", pc.view(data.cubes, {}, VK_IMAGE_VIEW_TYPE_CUBE_ARRAY), m.sampler)
                .storage("outImage", pc.view(data.out))
                .push(m.ctx, pc.cmd(), *p);
            BouncePush push{frame.camera.invViewProj, glm::vec4(frame.camera.position, invExposure),
                            glm::uvec4(e.width, e.height, count, 0u)};
            vkCmdPushConstants(pc.cmd(), p->layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
            vkCmdDispatch(pc.cmd(), (e.width + 7) / 8, (e.height + 7) / 8, 1);
        });
    return d.out;
}

}  // namespace speculum::probes
