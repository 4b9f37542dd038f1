// CMOs (SPECULUM_reflection_probe kind cmo, seed 000): validation, the arrays, one face's
// capture into them, the box mips of the radiance and the min/max distance hierarchy, the
// records in trace order, and the update modes (as local probes'). A CMO face is captured with
// the same passes as a local probe's (addCaptureFace: it sees the local probes' bake through
// probes.capture_bounce), then probes.cmo_store writes colour, distance and the attributes a
// hit is shaded with.
#include "module_impl.hpp"

#include "speculum/app/output.hpp"
#include "speculum/core.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>

namespace speculum::probes {
namespace {

using CmoRecord = shader::CmoRecord;
// The tracer walks CMOs in order for every uncovered pixel; eight bounds that loop (and seed
// 000 found that each CMO after the first few adds little).
constexpr size_t kMaxCmos = 8;
constexpr VkDeviceSize kMaxCmoBytes = VkDeviceSize(512) << 20;
// Bytes per texel of the four arrays: RGBA16F + RG32F + RGBA16F + RGBA8.
constexpr VkDeviceSize kCmoTexelBytes = 8 + 8 + 8 + 4;

struct StorePush {
    glm::mat4 invViewProj;
    glm::vec4 center;
    glm::uvec4 info;
};

std::vector<gpu::Unique<VkImageView>> mipViews(const gpu::Context& ctx, const gpu::Image& image) {
    std::vector<gpu::Unique<VkImageView>> views;
    for (uint32_t m = 0; m < image.desc().mips; ++m) {
        VkImageViewCreateInfo v{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        v.image = image.get();
        v.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
        v.format = image.desc().format;
        v.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, m, 1, 0, image.desc().layers};
        VkImageView view;
        gpu::check(vkCreateImageView(ctx.device(), &v, nullptr, &view), "vkCreateImageView");
        views.emplace_back(ctx.device(), view, vkDestroyImageView);
    }
    return views;
}

// How many of 14 rays from `center` (the axes and the cube's diagonals) first meet a triangle
// from behind (a single-sided one: double-sided materials face both ways). A point inside a
// closed mesh sees only back faces: the renderer culls them, so a CMO there would capture
// whatever lies beyond the mesh and trace a world that is not there.
int backFacesSeen(const Scene& scene, glm::vec3 center) {
    std::vector<glm::vec3> dirs = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int i = 0; i < 8; ++i)
        dirs.push_back(glm::normalize(glm::vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1)));
    std::vector<float> nearest(dirs.size(), std::numeric_limits<float>::infinity());
    std::vector<bool> back(dirs.size(), false);
    for (const Instance& inst : scene.instances) {
        const bool mirrored = glm::determinant(glm::mat3(inst.world)) < 0.0f;
        for (const Primitive& prim : scene.meshes.at(size_t(inst.mesh)).primitives) {
            bool twoSided = prim.material >= 0 && size_t(prim.material) < scene.materials.size() &&
                            scene.materials[size_t(prim.material)].doubleSided;
            for (size_t k = 0; k + 2 < prim.indices.size(); k += 3) {
                glm::vec3 a = glm::vec3(inst.world * glm::vec4(prim.vertices[prim.indices[k]].position, 1.0f));
                glm::vec3 b = glm::vec3(inst.world * glm::vec4(prim.vertices[prim.indices[k + 1]].position, 1.0f));
                glm::vec3 c = glm::vec3(inst.world * glm::vec4(prim.vertices[prim.indices[k + 2]].position, 1.0f));
                glm::vec3 e1 = b - a, e2 = c - a;
                glm::vec3 n = glm::cross(e1, e2) * (mirrored ? -1.0f : 1.0f);  // front: counter-clockwise
                for (size_t d = 0; d < dirs.size(); ++d) {
                    // Moller-Trumbore.
                    glm::vec3 pv = glm::cross(dirs[d], e2);
                    float det = glm::dot(e1, pv);
                    if (std::abs(det) < 1e-12f) continue;
                    glm::vec3 tv = center - a;
                    float u = glm::dot(tv, pv) / det;
                    if (u < 0.0f || u > 1.0f) continue;
                    glm::vec3 qv = glm::cross(tv, e1);
                    float v = glm::dot(dirs[d], qv) / det;
                    if (v < 0.0f || u + v > 1.0f) continue;
                    float t = glm::dot(e2, qv) / det;
                    if (t <= 1e-5f || t >= nearest[d]) continue;
                    nearest[d] = t;
                    back[d] = !twoSided && glm::dot(n, dirs[d]) > 0.0f;
                }
            }
        }
    }
    return int(std::count(back.begin(), back.end(), true));
}

// The arrays' mip that is a CMO's level 0: the one of its own face size (modules/probes/shaders/cmo.h).
uint32_t baseMip(uint32_t arrayFaceSize, const CmoInfo& info) {
    return uint32_t(std::countr_zero(arrayFaceSize / info.probe.resolution));
}

}  // namespace

void Probes::Impl::createCmos() {
    CmoState& c = cmo.emplace(CmoState{});
    const Scene& scene = renderer.scene();
    for (int i : activeProbeNodes(scene, ProbeKind::Cmo)) {
        ProbeInfo p = describeProbe(scene, i);
        c.list.push_back({i, p.name, p.probe, glm::vec3(scene.nodes[size_t(i)].world[3]), 0});
    }
    // Trace order: higher `order` first, then the file's order.
    std::stable_sort(c.list.begin(), c.list.end(),
                     [](const CmoInfo& a, const CmoInfo& b) { return a.probe.order > b.probe.order; });
    validateCmos();
    for (size_t i = 0; i < c.list.size(); ++i) {
        c.list[i].slot = uint32_t(i);
        c.faceSize = std::max(c.faceSize, c.list[i].probe.resolution);
    }
    c.mips = uint32_t(std::bit_width(c.faceSize));  // down to 1x1: the hierarchy's top is one cell
    const uint32_t layers = 6 * uint32_t(std::max<size_t>(c.list.size(), 1));
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                    VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    auto make = [&](VkFormat format, bool cube, const char* name) {
        return gpu::Image(ctx, {c.faceSize, c.faceSize, format, c.mips, layers, cube, usage}, name);
    };
    c.radiance = make(VK_FORMAT_R16G16B16A16_SFLOAT, true, "probes.cmo.radiance");
    c.distance = make(VK_FORMAT_R32G32_SFLOAT, false, "probes.cmo.distance");
    c.attr = make(VK_FORMAT_R16G16B16A16_SFLOAT, false, "probes.cmo.attr");
    c.albedo = make(VK_FORMAT_R8G8B8A8_UNORM, false, "probes.cmo.albedo");
    c.radianceMips = mipViews(ctx, c.radiance);
    c.distanceMips = mipViews(ctx, c.distance);
    c.attrMips = mipViews(ctx, c.attr);
    c.albedoMips = mipViews(ctx, c.albedo);
    c.records = gpu::Buffer(ctx, sizeof(CmoRecord) * std::max<size_t>(c.list.size(), 1),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "probes.cmo.records");
    std::memset(c.records.mapped(), 0, c.records.size());
    // Per material index (the G-buffer's): 1 for mirrors that reflect again (self-reflections).
    std::vector<float> mirrors;
    for (const Material& m : scene.materials) mirrors.push_back(reflectionsOf(m).mirrorForSelfReflections ? 1.0f : 0.0f);
    mirrors.push_back(0.0f);  // glTF's default material
    mirrors.resize(std::min<size_t>(mirrors.size(), render::kMaxIndexedMaterials + 1));
    c.mirrorCount = uint32_t(mirrors.size());
    c.mirrors = gpu::uploadBuffer(ctx, std::as_bytes(std::span(mirrors)), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                  "probes.cmo.mirrors");
    c.store = gpu::createComputePipeline(ctx, "probes/cmo_store.comp", sizeof(StorePush), "probes.cmo_store");
    c.reduce = gpu::createComputePipeline(ctx, "probes/cmo_reduce.comp", sizeof(glm::uvec4), "probes.cmo_hierarchy");
    c.pending.assign(c.list.size(), false);
    c.ready.assign(c.list.size(), false);
    c.blind.assign(c.list.size(), false);
    c.relocating.assign(c.list.size(), -1);
    c.movedAgain.assign(c.list.size(), false);
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        // Far everywhere until captured: a CMO is traced only once its record is written.
        VkClearColorValue far{};
        far.float32[0] = far.float32[1] = float(SPECULUM_CMO_SKY_DISTANCE);
        VkClearColorValue black{};
        VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
        for (const gpu::Image* image : {&c.radiance, &c.distance, &c.attr, &c.albedo}) {
            gpu::transition(cmd, image->get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                            VK_IMAGE_LAYOUT_GENERAL);
            vkCmdClearColorImage(cmd, image->get(), VK_IMAGE_LAYOUT_GENERAL, image == &c.distance ? &far : &black, 1,
                                 &all);
        }
    });
}

void Probes::Impl::validateCmos() const {
    const std::string file = renderer.scene().path.string();
    const VkPhysicalDeviceLimits& limits = ctx.properties().limits;
    const std::vector<CmoInfo>& list = cmo->list;
    uint32_t largest = 16;
    for (const CmoInfo& c : list) {
        uint32_t res = c.probe.resolution;
        const std::string where = c.name + ".extensions.SPECULUM_reflection_probe.resolution: " + std::to_string(res);
        if (res < 16 || !std::has_single_bit(res))
            throw inputError(file, where + " is not a power of two >= 16 (a CMO's distance hierarchy halves it to 1)");
        if (res > limits.maxImageDimensionCube)
            throw inputError(file, where + " exceeds the device's cube limit of " +
                                       std::to_string(limits.maxImageDimensionCube) + " (" + ctx.deviceName() + ")");
        largest = std::max(largest, res);
    }
    for (const CmoInfo& c : list) {
        int back = backFacesSeen(renderer.scene(), c.center);
        if (back >= 10)
            throw inputError(file, c.name + ": the CMO's centre is inside geometry (" + std::to_string(back) +
                                       " of 14 rays from it meet a back face first): move it into the open");
    }
    if (list.size() > kMaxCmos)
        throw inputError(file, std::to_string(list.size()) + " CMOs; the tracer takes at most " +
                                   std::to_string(kMaxCmos) + " (" + list[kMaxCmos].name + " is one too many)");
    VkDeviceSize bytes = VkDeviceSize(largest) * largest * 6 * list.size() * kCmoTexelBytes * 4 / 3;
    if (bytes > kMaxCmoBytes)
        throw inputError(file, std::to_string(list.size()) + " CMOs at " + std::to_string(largest) +
                                   "^2 faces take " + std::to_string(bytes >> 20) + " MiB, over the " +
                                   std::to_string(kMaxCmoBytes >> 20) + " MiB budget: lower their resolution");
}

void Probes::Impl::captureCmoFace(size_t index, uint32_t face) {
    CmoState& c = *cmo;
    const CmoInfo& info = c.list[index];
    const uint32_t res = info.probe.resolution;
    const uint32_t base = baseMip(c.faceSize, info);
    const uint32_t layer = 6 * info.slot + face;
    FrameGraph fg(FrameGraphConfig{res, res});
    CaptureFace cap = addCaptureFace(fg, info.center, face, res);
    auto import = [&](const gpu::Image& image, const char* name) {
        return fg.importTexture(name, descOf(image),
                                {image.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL, image.desc().usage});
    };
    struct Store {
        render::GBuffer g;
        TextureHandle face, radiance, distance, attr, albedo;
    };
    const Subresource target{base, 1, layer, 1};
    const auto& s = fg.addPass<Store>(
        "probes.cmo_store", PassType::Compute,
        [&](PassBuilder& pb, Store& d) {
            d.g = render::readSurfaceAttachments(pb, cap.g);
            if (cap.g.shadowMask.valid()) d.g.shadowMask = pb.read(cap.g.shadowMask, TextureUsage::Sampled);
            d.face = pb.read(cap.face, TextureUsage::Sampled);
            d.radiance = pb.write(import(c.radiance, "probes.cmo.radiance"), TextureUsage::StorageWrite, target);
            d.distance = pb.write(import(c.distance, "probes.cmo.distance"), TextureUsage::StorageWrite, target);
            d.attr = pb.write(import(c.attr, "probes.cmo.attr"), TextureUsage::StorageWrite, target);
            d.albedo = pb.write(import(c.albedo, "probes.cmo.albedo"), TextureUsage::StorageWrite, target);
        },
        [this, &c, &info, frame = cap.frame, res, target](const Store& d, PassContext& pc) {
            c.store.bind(pc.cmd());
            // No shadowed light: the face's own flat 1 (the shadow mask's dummy is the renderer's).
            VkImageView mask = d.g.shadowMask.valid() ? pc.view(d.g.shadowMask) : pc.view(d.face);
            gpu::DescriptorWriter()
                .sampled("depthTex", pc.view(d.g.depth), nearest)
                .sampled("albedoTex", pc.view(d.g.albedo), nearest)
                .sampled("normalTex", pc.view(d.g.normal), nearest)
                .sampled("emissiveTex", pc.view(d.g.emissive), nearest)
                .sampled("faceTex", pc.view(d.face), nearest)
                .sampled("shadowMask", mask, nearest)
                .buffer("MirrorTable", c.mirrors.get())
                .storage("outRadiance", pc.view(d.radiance, target, VK_IMAGE_VIEW_TYPE_2D))
                .storage("outDistance", pc.view(d.distance, target, VK_IMAGE_VIEW_TYPE_2D))
                .storage("outAttr", pc.view(d.attr, target, VK_IMAGE_VIEW_TYPE_2D))
                .storage("outAlbedo", pc.view(d.albedo, target, VK_IMAGE_VIEW_TYPE_2D))
                .push(ctx, pc.cmd(), c.store);
            StorePush p{frame.camera.invViewProj, glm::vec4(info.center, 0.0f),
                        glm::uvec4(res, c.mirrorCount, d.g.shadowMask.valid() ? 1u : 0u, 0u)};
            vkCmdPushConstants(pc.cmd(), c.store.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(p), &p);
            vkCmdDispatch(pc.cmd(), (res + 7) / 8, (res + 7) / 8, 1);
        });
    fg.markOutput(s.radiance);
    fg.markOutput(s.distance);
    fg.markOutput(s.attr);
    fg.markOutput(s.albedo);
    c.ms += runCapture(fg);
    ++c.faces;
}

void Probes::Impl::finishCmo(size_t index) {
    CmoState& c = *cmo;
    const CmoInfo& info = c.list[index];
    const uint32_t base = baseMip(c.faceSize, info);
    const uint32_t layer = 6 * info.slot;
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        for (uint32_t m = base + 1; m < c.mips; ++m) {
            const uint32_t size = std::max(c.faceSize >> m, 1u);
            // The blit's own layouts (GENERAL is allowed, and the validation layers warn about it).
            gpu::transition(cmd, c.radiance.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL,
                            VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, m - 1, 1, layer, 6);
            gpu::transition(cmd, c.radiance.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL,
                            VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, m, 1, layer, 6);
            gpu::transition(cmd, c.distance.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL,
                            VK_IMAGE_LAYOUT_GENERAL, m - 1, 1, layer, 6);
            // Radiance: a box mip for glossy rays' cone footprints.
            VkImageBlit blit{};
            blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, m - 1, layer, 6};
            blit.srcOffsets[1] = {int32_t(size * 2), int32_t(size * 2), 1};
            blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, m, layer, 6};
            blit.dstOffsets[1] = {int32_t(size), int32_t(size), 1};
            vkCmdBlitImage(cmd, c.radiance.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.radiance.get(),
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
            gpu::transition(cmd, c.radiance.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                            VK_IMAGE_LAYOUT_GENERAL, m - 1, 1, layer, 6);
            gpu::transition(cmd, c.radiance.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                            VK_IMAGE_LAYOUT_GENERAL, m, 1, layer, 6);
            // Distance: min and max of the four cells below.
            c.reduce.bind(cmd);
            gpu::DescriptorWriter()
                .sampled("finer", c.distanceMips[m - 1].get(), nearest.get(), VK_IMAGE_LAYOUT_GENERAL)
                .storage("coarser", c.distanceMips[m].get())
                .push(ctx, cmd, c.reduce);
            glm::uvec4 push(size, layer, 0u, 0u);
            vkCmdPushConstants(cmd, c.reduce.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
            vkCmdDispatch(cmd, (size + 7) / 8, (size + 7) / 8, 6);
        }
        gpu::transition(cmd, c.radiance.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL,
                        VK_IMAGE_LAYOUT_GENERAL);
        gpu::transition(cmd, c.distance.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL,
                        VK_IMAGE_LAYOUT_GENERAL);
    });
    // A CMO whose faces saw only sky (its top cells' nearest surface is the sky) would trace
    // nothing: it is left out of the chain, with a warning (the documented fallback).
    bool seesSomething = false;
    for (uint32_t f = 0; f < 6 && !seesSomething; ++f)
        seesSomething = gpu::readImageRGBA(ctx, c.distance.get(), c.distance.desc(), VK_IMAGE_LAYOUT_GENERAL,
                                           c.mips - 1, layer + f)[0] < 0.5f * float(SPECULUM_CMO_SKY_DISTANCE);
    if (!seesSomething) {
        if (!c.blind[index])
            logWarning(renderer.scene().path.string() + ": " + info.name +
                       ": the CMO sees nothing (every face is sky); it is left out of CMO tracing");
        c.blind[index] = true;
        return;
    }
    c.blind[index] = false;
    c.ready[index] = true;
    writeCmoRecords();
}

uint32_t Probes::Impl::writeCmoRecords() {
    CmoState& c = *cmo;
    auto* out = static_cast<CmoRecord*>(c.records.mapped());
    uint32_t n = 0;
    for (size_t i = 0; i < c.list.size(); ++i) {
        if (!c.ready[i]) continue;
        const CmoInfo& info = c.list[i];
        const uint32_t res = info.probe.resolution;
        const uint32_t base = baseMip(c.faceSize, info);
        out[n++] = {glm::vec4(info.center, float(res)),
                    glm::vec4(float(6 * info.slot), float(base), float(std::bit_width(res)), 2.0f / float(res))};
    }
    return n;
}

void Probes::Impl::updateCmos(const Progress& progress) {
    CmoState& c = *cmo;
    std::vector<size_t> full, sliced;
    for (size_t i = 0; i < c.list.size(); ++i) {
        ProbeUpdate mode = c.list[i].probe.update;
        // Not yet baked (a blind CMO counts as baked: it is not captured again unless asked; a
        // moved one is captured again a face per update by stepRelocations).
        bool start = !c.ready[i] && !c.blind[i] && c.relocating[i] < 0 && mode != ProbeUpdate::TimeSliced;
        if (start || c.pending[i] || mode == ProbeUpdate::EveryFrame) full.push_back(i);
        else if (mode == ProbeUpdate::TimeSliced) sliced.push_back(i);
    }
    size_t done = 0, total = full.size() * 6;
    for (size_t i : full) {
        for (uint32_t f = 0; f < 6; ++f) {
            captureCmoFace(i, f);
            if (progress) progress(++done, total);
        }
        finishCmo(i);
        c.pending[i] = false;
    }
    if (!sliced.empty()) {
        size_t i = sliced[(c.slice / 6) % sliced.size()];
        uint32_t face = uint32_t(c.slice % 6);
        captureCmoFace(i, face);
        if (face == 5) finishCmo(i);
        ++c.slice;
    }
}

}  // namespace speculum::probes
