// The probes module's entry point and bookkeeping: probe records from the scene, validation
// against the device, the cube array, update modes, and the frame graph imports.
#include "module_impl.hpp"

#include "speculum/app/output.hpp"
#include "speculum/core.hpp"
#include "speculum/render/frustum.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

namespace speculum::probes {
namespace {

constexpr VkFormat kCubeFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
// The blend loop walks every probe for every reflective pixel: 64 keeps that loop bounded (and
// a 64 x 6-layer array of 256^2 faces at 0.5 GiB fits lavapipe's 2 GiB heap).
constexpr size_t kMaxProbes = 64;
constexpr VkDeviceSize kMaxArrayBytes = VkDeviceSize(1) << 30;

// The bytes of `cubes` RGBA16F cubes of `face`^2 faces with their mip chains (4/3).
VkDeviceSize cubeArrayBytes(uint32_t face, size_t cubes) {
    return VkDeviceSize(face) * face * 8 * 6 * cubes * 4 / 3;
}

}  // namespace

std::string probeName(const Scene& scene, int node) {
    const std::string& n = scene.nodes[size_t(node)].name;
    return "nodes[" + std::to_string(node) + "]" + (n.empty() ? "" : " \"" + n + "\"");
}

ProbeInfo describeProbe(const ReflectionProbe& probe, const glm::mat4& world, std::string name) {
    ProbeInfo info;
    info.name = std::move(name);
    info.probe = probe;
    const ReflectionProbe& p = info.probe;
    info.gpu.worldToLocal = glm::inverse(world);
    info.gpu.center = glm::vec4(glm::vec3(world[3]), p.shape == ProbeShape::Sphere ? 1.0f : 0.0f);
    info.gpu.extents = glm::vec4(p.extents, p.blendDistance);
    float det = std::abs(glm::determinant(glm::mat3(world)));
    info.volume = p.shape == ProbeShape::Sphere
                      ? 4.0f / 3.0f * std::numbers::pi_v<float> * p.extents.x * p.extents.x * p.extents.x * det
                      : 8.0f * p.extents.x * p.extents.y * p.extents.z * det;
    return info;
}

ProbeInfo describeProbe(const Scene& scene, int node) {
    const Node& n = scene.nodes.at(size_t(node));
    ProbeInfo info = describeProbe(n.probe.value_or(ReflectionProbe{}), n.world, probeName(scene, node));
    info.node = node;
    return info;
}

bool wantsAutoProbe(const Scene& scene) {
    if (!activeProbeNodes(scene, ProbeKind::LocalCubemap).empty()) return false;
    const glm::vec3 size = scene.boundsMax - scene.boundsMin;
    return !scene.instances.empty() && std::isfinite(size.x + size.y + size.z) && size.x > 0.0f && size.z > 0.0f;
}

namespace {

// The world bounds of every primitive of every instance (empty ones have none, as in the
// scene's own bounds).
std::vector<std::pair<glm::vec3, glm::vec3>> primitiveBounds(const Scene& scene) {
    std::vector<std::pair<glm::vec3, glm::vec3>> out;
    for (const Instance& inst : scene.instances)
        for (const Primitive& prim : scene.meshes.at(size_t(inst.mesh)).primitives) {
            if (prim.vertices.empty()) continue;
            glm::vec3 lo, hi;
            render::transformBox(inst.world, prim.boundsMin, prim.boundsMax, lo, hi);
            out.emplace_back(lo, hi);
        }
    return out;
}

}  // namespace

ProbeInfo autoProbe(const Scene& scene) {
    // The box spans the scene's bounds across (a plain export's floor is its widest thing) and
    // stands on their floor. It is at least half as tall as it is wide: its centre, where it is
    // captured, then sees the floor from above, and a ray that leaves the scene upwards meets the
    // box's top far enough off that its parallax lands on sky. Measured on plain_metals (16 x 2 x
    // 16 m of bounds, main camera, mirror band): as tall as the bounds (2 m, captured at 1 m)
    // 17.8 dB, worse than no probe (19.1: the sky seen through a low lid is misplaced); 4 m
    // 22.7 dB; 8 m, this rule's, 22.8 dB. 1% margin so that the floor lies inside.
    const glm::vec3 lo = scene.boundsMin, hi = scene.boundsMax;
    const glm::vec3 half = 0.5f * (hi - lo) * 1.01f;
    const float halfHeight = std::max(half.y, 0.5f * std::max(half.x, half.z));
    ReflectionProbe p;
    p.kind = ProbeKind::LocalCubemap;
    p.shape = ProbeShape::Box;
    p.extents = glm::vec3(half.x, halfHeight, half.z);
    p.blendDistance = 0.5f;
    p.resolution = 128;
    p.update = ProbeUpdate::Once;
    const glm::vec3 centre(0.5f * (lo.x + hi.x), lo.y - 0.01f * (hi.y - lo.y) + halfHeight, 0.5f * (lo.z + hi.z));
    ProbeInfo info = describeProbe(p, glm::translate(glm::mat4(1.0f), centre), "the automatic probe (probes.auto_probe)");
    // The capture point (the shaders take it apart from the box: probes.glsl) starts at the
    // centre and, where a primitive's bounds hold it, climbs halfway from that primitive's top to
    // the box's top. Inside an object it would capture the object's inside (cube_camera_repro's
    // cube holds the centre: its top then reflected black); just above one, the object fills its
    // lower hemisphere (from 0.1 m above that cube, the cube's sides reflected its dark top where
    // the emissive floor is); halfway, a 2 m cube hides a 45-degree cone below and the floor
    // around it is seen. Bounds, not triangles: a double-sided closed mesh has no back face to
    // tell its inside by.
    const float top = centre.y + halfHeight, step = 0.05f * halfHeight, margin = 0.25f * step;
    glm::vec3 eye = centre;
    const auto boxes = primitiveBounds(scene);
    for (bool moved = true; moved;) {
        moved = false;
        for (const auto& [blo, bhi] : boxes)
            if (glm::all(glm::greaterThanEqual(eye, blo - margin)) && glm::all(glm::lessThanEqual(eye, bhi + margin)) &&
                bhi.y + step < top) {
                eye.y = 0.5f * (bhi.y + top);
                moved = true;
            }
    }
    info.gpu.center = glm::vec4(eye, info.gpu.center.w);
    return info;
}

void sortForBlending(std::vector<ProbeInfo>& probes) {
    std::stable_sort(probes.begin(), probes.end(), [](const ProbeInfo& a, const ProbeInfo& b) {
        if (a.probe.order != b.probe.order) return a.probe.order > b.probe.order;
        return a.volume < b.volume;
    });
}

render::CameraState faceCamera(glm::vec3 center, uint32_t face, uint32_t size, float znear) {
    // Forward and the face's t axis (Vulkan cube face selection). The camera's up is t, so its
    // right is forward x t = the face's s axis; rows then run against t, and the capture stores
    // the face flipped vertically.
    static const glm::vec3 forward[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    static const glm::vec3 tAxis[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
    return render::makeCamera(center, center + forward[face], tAxis[face], glm::radians(90.0f), size, size, znear);
}

Probes::Impl::Impl(const gpu::Context& c, render::Renderer& r, const ProbeSettings& s)
    : ctx(c), renderer(r), settings(s),
      sampler(gpu::createSampler(c, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, true)),
      nearest(gpu::createSampler(c, VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, false)),
      bounce(gpu::createComputePipeline(c, "probes/capture_bounce.comp", 96, "probes.capture_bounce")),
      distanceStore(gpu::createComputePipeline(c, "probes/distance_store.comp", 96, "probes.distance_store")),
      filter(c), allocator(c.physicalDevice(), c.device()),
      executor(c.instance(), c.physicalDevice(), c.device(), c.timestampPeriodNs()) {
    const Scene& scene = r.scene();
    for (int i : activeProbeNodes(scene, ProbeKind::LocalCubemap)) probes.push_back(describeProbe(scene, i));
    if (settings.autoProbe && wantsAutoProbe(scene)) probes.push_back(autoProbe(scene));
    sortForBlending(probes);
    validate();
    allocate();
    createCmos();
    createPlanar();
    allocateBelow();
}

void Probes::Impl::validate() const {
    const std::string file = renderer.scene().path.string();
    const VkPhysicalDeviceLimits& limits = ctx.properties().limits;
    for (const ProbeInfo& p : probes) {
        uint32_t res = p.probe.resolution;
        if (res < 8 || !std::has_single_bit(res))
            throw inputError(file, p.name + ".extensions.SPECULUM_reflection_probe.resolution: " + std::to_string(res) +
                                       " is not a power of two >= 8");
        if (res > limits.maxImageDimensionCube)
            throw inputError(file, p.name + ".extensions.SPECULUM_reflection_probe.resolution: " + std::to_string(res) +
                                       " exceeds the device's cube limit of " +
                                       std::to_string(limits.maxImageDimensionCube) + " (" + ctx.deviceName() + ")");
    }
    size_t capacity = std::min<size_t>(kMaxProbes, limits.maxImageArrayLayers / 6);
    if (probes.size() > capacity)
        throw inputError(file, std::to_string(probes.size()) + " local cubemap probes; the cube array holds " +
                                   std::to_string(capacity) + " (" + probes[capacity].name + " is one too many)");
    // Every cube of the array takes the largest probe's face size: name that probe.
    const ProbeInfo* largest = nullptr;
    for (const ProbeInfo& p : probes)
        if (!largest || p.probe.resolution > largest->probe.resolution) largest = &p;
    uint32_t size = largest ? std::max(8u, largest->probe.resolution) : 8u;
    VkDeviceSize bytes = cubeArrayBytes(size, std::max<size_t>(probes.size(), 1));
    if (bytes > kMaxArrayBytes)
        throw inputError(file, largest->name + ".extensions.SPECULUM_reflection_probe.resolution: " +
                                   std::to_string(size) + " makes the probes' cube array (" +
                                   std::to_string(probes.size()) + " cubes of " + std::to_string(size) +
                                   "^2 faces, each cube at the largest probe's resolution) take " +
                                   std::to_string(bytes >> 20) + " MiB, over the " +
                                   std::to_string(kMaxArrayBytes >> 20) +
                                   " MiB budget: lower the resolution or use fewer probes");
}

void Probes::Impl::allocate() {
    for (const ProbeInfo& p : probes) faceSize = std::max(faceSize, p.probe.resolution);
    mips = uint32_t(std::bit_width(faceSize)) - 2;  // down to 4x4, as the sky's cube
    const uint32_t count = uint32_t(std::max<size_t>(probes.size(), 1));
    const VkImageUsageFlags usage =
        VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
        VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    cubes = gpu::Image(ctx, {faceSize, faceSize, kCubeFormat, mips, 6 * count, true, usage}, "probes.cubes");
    distances = gpu::Image(ctx, {faceSize, faceSize, VK_FORMAT_R16G16B16A16_SFLOAT, 1, 6 * count, true,
                                 VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                                     VK_IMAGE_USAGE_TRANSFER_SRC_BIT},  // SRC: the tests read it back
                           "probes.distances");
    for (size_t i = 0; i < probes.size(); ++i) {
        uint32_t res = probes[i].probe.resolution;
        radiance.emplace_back(ctx, gpu::ImageDesc{res, res, kCubeFormat, uint32_t(std::bit_width(res)), 6, true, usage},
                              "probes.radiance." + std::to_string(i));
        std::vector<gpu::Unique<VkImageView>> views;
        for (uint32_t m = 0; m < mips; ++m) {
            VkImageViewCreateInfo v{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
            v.image = cubes.get();
            v.viewType = VK_IMAGE_VIEW_TYPE_CUBE;
            v.format = kCubeFormat;
            v.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, m, 1, uint32_t(6 * i), 6};
            VkImageView view;
            gpu::check(vkCreateImageView(ctx.device(), &v, nullptr, &view), "vkCreateImageView");
            views.emplace_back(ctx.device(), view, vkDestroyImageView);
        }
        targetViews.push_back(std::move(views));
        probes[i].gpu.params = glm::vec4(float(i), float(mips - 1), float(settings.distanceSteps), 0.0f);
    }
    steps = render::planPrefilterSteps(faceSize, mips, 0, uint32_t(settings.prefilterSamples),
                                       uint64_t(settings.prefilterSlice) * 1024);
    wholePlan = render::planPrefilterSteps(faceSize, mips, 0, uint32_t(settings.prefilterSamples), ~uint64_t(0));
    pending.assign(probes.size(), false);
    ready.assign(probes.size(), false);
    relocating.assign(probes.size(), -1);
    movedAgain.assign(probes.size(), false);
    records = gpu::Buffer(ctx, sizeof(shader::Probe) * count, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "probes.records");
    std::memset(records.mapped(), 0, records.size());
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        // Black until baked: a probe is blended only once its record is written (ready).
        gpu::transition(cmd, cubes.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
        VkClearColorValue black{};
        VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
        vkCmdClearColorImage(cmd, cubes.get(), VK_IMAGE_LAYOUT_GENERAL, &black, 1, &all);
        gpu::transition(cmd, cubes.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL,
                        VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        // The sky everywhere until a capture writes a face.
        VkClearColorValue far{{65504.0f, 0.0f, 0.0f, 0.0f}};  // no mirror either
        gpu::transition(cmd, distances.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
        vkCmdClearColorImage(cmd, distances.get(), VK_IMAGE_LAYOUT_GENERAL, &far, 1, &all);
        for (const gpu::Image& r : radiance) {
            gpu::transition(cmd, r.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
            vkCmdClearColorImage(cmd, r.get(), VK_IMAGE_LAYOUT_GENERAL, &black, 1, &all);
        }
    });
}

void Probes::Impl::allocateBelow() {
    const gpu::ImageDesc& d = cubes.desc();
    // Half the array budget: with `below` the probes take both (validate() checks one).
    const VkDeviceSize bytes = cubeArrayBytes(d.width, d.layers / 6);
    if (planar.list.empty() || probes.empty() || settings.bounces < 2 || 2 * bytes > kMaxArrayBytes) return;
    below = gpu::Image(ctx, d, "probes.cubes_below");
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        gpu::transition(cmd, below.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
        VkClearColorValue black{};
        VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
        vkCmdClearColorImage(cmd, below.get(), VK_IMAGE_LAYOUT_GENERAL, &black, 1, &all);
    });
}

void Probes::Impl::keepBelow(size_t index) {
    if (below.get() == VK_NULL_HANDLE || lastRound) return;
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        const uint32_t first = uint32_t(6 * index);
        gpu::transition(cmd, cubes.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                        VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 0, VK_REMAINING_MIP_LEVELS, first, 6);
        gpu::transition(cmd, below.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_GENERAL,
                        VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_REMAINING_MIP_LEVELS, first, 6);
        std::vector<VkImageCopy> copies(mips);
        for (uint32_t m = 0; m < mips; ++m) {
            const uint32_t size = std::max(faceSize >> m, 1u);
            copies[m].srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, m, first, 6};
            copies[m].dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, m, first, 6};
            copies[m].extent = {size, size, 1};
        }
        vkCmdCopyImage(cmd, cubes.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, below.get(),
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, mips, copies.data());
        gpu::transition(cmd, below.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                        VK_IMAGE_LAYOUT_GENERAL, 0, VK_REMAINING_MIP_LEVELS, first, 6);
        gpu::transition(cmd, cubes.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                        VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, 0, VK_REMAINING_MIP_LEVELS, first, 6);
    });
}

uint32_t Probes::Impl::readyCount() const {
    return uint32_t(std::count(ready.begin(), ready.end(), true));
}

uint32_t Probes::Impl::writeRecords() {
    auto* out = static_cast<shader::Probe*>(records.mapped());
    uint32_t n = 0;
    for (size_t i = 0; i < probes.size(); ++i)
        if (ready[i]) out[n++] = probes[i].gpu;
    return n;
}

Probes::Probes(const gpu::Context& ctx, render::Renderer& renderer, const ProbeSettings& settings)
    : impl_(std::make_unique<Impl>(ctx, renderer, settings)) {}
Probes::~Probes() = default;

const std::vector<ProbeInfo>& Probes::probes() const { return impl_->probes; }
const std::vector<CmoInfo>& Probes::cmos() const { return impl_->cmo->list; }
const gpu::Image& Probes::cmoDistance() const { return impl_->cmo->distance; }
const gpu::Image& Probes::cmoRadiance() const { return impl_->cmo->radiance; }
const gpu::Image& Probes::cubes() const { return impl_->cubes; }
const gpu::Image& Probes::distances() const { return impl_->distances; }
size_t Probes::timeSlicedCycle() const { return impl_->timeSlicedCycle(); }
size_t Probes::facesCaptured() const { return impl_->faces; }
double Probes::captureMs() const { return impl_->ms; }
size_t Probes::cmoFacesCaptured() const { return impl_->cmo->faces; }
double Probes::cmoCaptureMs() const { return impl_->cmo->ms; }

void Probes::requestUpdate(int probe) {
    Impl& m = *impl_;
    // The whole scene changed (an edit, a taken gem): the grounds too (renderGrounds returns at
    // once where there are none).
    if (probe < 0) m.planar.groundValid = false;
    for (size_t i = 0; i < m.pending.size(); ++i)
        if (probe < 0 || size_t(probe) == i) m.pending[i] = true;
    // CMOs follow the local probes in this numbering.
    for (size_t i = 0; i < m.cmo->pending.size(); ++i)
        if (probe < 0 || size_t(probe) == m.pending.size() + i) m.cmo->pending[i] = true;
}

void Probes::Impl::bakeAll(const std::vector<size_t>& which, const Progress& progress, size_t& done, size_t total) {
    for (size_t i : which) {
        for (uint32_t f = 0; f < 6; ++f) {
            captureFace(i, f);
            if (progress) progress(++done, total);
        }
        prefilter(i, wholePlan, 0);
    }
}

Probes::Progress Probes::terminalProgress() {
    return [](size_t done, size_t total) { app::progress("probe bake (faces)", done, total); };
}

void Probes::update(const Progress& progress) {
    Impl& m = *impl_;
    std::vector<size_t> full, sliced;
    for (size_t i = 0; i < m.probes.size(); ++i) {
        ProbeUpdate mode = m.probes[i].probe.update;
        bool start = !m.baked && (mode == ProbeUpdate::Once || mode == ProbeUpdate::OnDemand);
        if (start || m.pending[i] || mode == ProbeUpdate::EveryFrame) full.push_back(i);
        else if (mode == ProbeUpdate::TimeSliced) sliced.push_back(i);
    }
    // The grounds before the bakes that read them (capture_bounce); on the first update they see
    // only the sky, as a bake's first round does.
    if (!m.planar.groundValid) m.renderGrounds();
    // Bounces: at start every bake after the first sees the one before it.
    int rounds = m.baked ? 1 : m.settings.bounces;
    size_t done = 0, total = full.size() * 6 * size_t(rounds);
    for (int b = 0; b < rounds && !full.empty(); ++b) {
        m.lastRound = rounds > 1 && b == rounds - 1;
        m.bakeAll(full, progress, done, total);
        m.baked = true;
    }
    m.lastRound = false;
    for (size_t i : full) m.pending[i] = false;
    if (!sliced.empty()) {
        if (m.cycleStep(sliced[m.slicedProbe % sliced.size()], m.slicedStep++)) {
            m.slicedStep = 0;
            ++m.slicedProbe;
        }
    }
    m.baked = m.baked || !full.empty();
    m.stepRelocations();
    // CMOs after the probes: their captures see the probes' bake (capture_bounce).
    m.updateCmos(progress ? Progress([](size_t done, size_t total) { app::progress("CMO bake (faces)", done, total); })
                          : Progress{});
}

namespace {

// Starts a capture cycle at face 0, or, when one is under way, has it start once more after it.
void restartCycle(int& next, std::vector<bool>::reference again) {
    if (next < 0) next = 0;
    else again = true;
}

}  // namespace

void Probes::recapture(int probe) {
    Impl& m = *impl_;
    if (probe < 0) m.planar.groundValid = false;
    for (size_t i = 0; i < m.probes.size(); ++i)
        if (probe < 0 || size_t(probe) == i) restartCycle(m.relocating[i], m.movedAgain[i]);
    // A CMO in place keeps `ready`: its distances stay relative to the same centre.
    Impl::CmoState& c = *m.cmo;
    for (size_t i = 0; i < c.list.size(); ++i)
        if (probe < 0 || size_t(probe) == m.probes.size() + i) restartCycle(c.relocating[i], c.movedAgain[i]);
}

bool Probes::moveProbe(int node, const glm::mat4& world) {
    Impl& m = *impl_;
    for (size_t i = 0; i < m.probes.size(); ++i) {
        if (m.probes[i].node != node) continue;
        m.probes[i].gpu.worldToLocal = glm::inverse(world);
        m.probes[i].gpu.center = glm::vec4(glm::vec3(world[3]), m.probes[i].gpu.center.w);
        restartCycle(m.relocating[i], m.movedAgain[i]);
        m.writeRecords();
        return true;
    }
    Impl::CmoState& c = *m.cmo;
    for (size_t i = 0; i < c.list.size(); ++i) {
        if (c.list[i].node != node) continue;
        c.list[i].center = glm::vec3(world[3]);
        c.ready[i] = false;
        restartCycle(c.relocating[i], c.movedAgain[i]);
        m.writeCmoRecords();
        return true;
    }
    return false;
}

bool Probes::relocating() const {
    const Impl& m = *impl_;
    auto any = [](const std::vector<int>& v) { return std::any_of(v.begin(), v.end(), [](int f) { return f >= 0; }); };
    return any(m.relocating) || any(m.cmo->relocating);
}

void Probes::Impl::stepRelocations() {
    // One step an update, for the first probe or CMO with a cycle under way: a face capture
    // costs a frame of its own size, and several at once were the hitch the cycle exists to
    // avoid (a gem taken in the game re-captures the probe and both CMOs: three faces an update
    // made 120-125 ms frames at 320x180, against 42). Local probes first, as in update(): a
    // CMO's capture then sees the probes' new bake (capture_bounce).
    // A local probe's cycle is the time-sliced one: six faces, then the prefilter's steps.
    for (size_t i = 0; i < probes.size(); ++i) {
        if (relocating[i] < 0) continue;
        if (!cycleStep(i, size_t(relocating[i]))) {
            ++relocating[i];
            return;
        }
        relocating[i] = movedAgain[i] ? 0 : -1;
        movedAgain[i] = false;
        return;
    }
    CmoState& c = *cmo;
    for (size_t i = 0; i < c.list.size(); ++i) {
        if (c.relocating[i] < 0) continue;
        uint32_t face = uint32_t(c.relocating[i]);
        captureCmoFace(i, face);
        if (face < 5) {
            ++c.relocating[i];
            return;
        }
        c.relocating[i] = c.movedAgain[i] ? 0 : -1;
        c.movedAgain[i] = false;
        // Traced again once a whole cycle from one place is done.
        if (c.relocating[i] < 0) finishCmo(i);
        return;
    }
}

ProbeSet Probes::addPasses(FrameGraph& graph, bool enabled, bool cmos) {
    Impl& m = *impl_;
    ProbeSet set;
    const gpu::ImageDesc& d = m.cubes.desc();
    set.cubes = graph.importTexture("probes.cubes",
                                    {.width = d.width, .height = d.height, .format = d.format, .mips = d.mips,
                                     .layers = d.layers, .cube = true},
                                    {m.cubes.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, d.usage});
    set.distances = graph.importTexture("probes.distances", descOf(m.distances),
                                        {m.distances.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                                         m.distances.desc().usage});
    set.records = graph.importBuffer("probes.records", {m.records.size()}, {m.records.get()});
    set.count = enabled ? m.readyCount() : 0;
    const Impl::CmoState& c = *m.cmo;
    auto import = [&](const gpu::Image& image, const char* name) {
        return graph.importTexture(name, descOf(image),
                                   {image.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL, image.desc().usage});
    };
    set.cmos.radiance = import(c.radiance, "probes.cmo.radiance");
    set.cmos.distance = import(c.distance, "probes.cmo.distance");
    set.cmos.attr = import(c.attr, "probes.cmo.attr");
    set.cmos.albedo = import(c.albedo, "probes.cmo.albedo");
    set.cmos.records = graph.importBuffer("probes.cmo.records", {c.records.size()}, {c.records.get()});
    set.cmos.count = cmos ? uint32_t(std::count(c.ready.begin(), c.ready.end(), true)) : 0;
    set.planar.images = import(m.planar.images, "probes.planar");
    set.planar.records = graph.importBuffer("probes.planar.records", {m.planar.records.size()}, {m.planar.records.get()});
    set.planar.count = enabled ? m.planar.rendered : 0;
    set.planar.ground = import(m.planar.ground, "probes.planar_ground");
    set.planar.groundRecords = graph.importBuffer("probes.ground_records", {m.planar.groundRecords.size()},
                                                  {m.planar.groundRecords.get()});
    set.planar.groundCount = enabled ? m.planar.groundCount : 0;
    return set;
}

}  // namespace speculum::probes
