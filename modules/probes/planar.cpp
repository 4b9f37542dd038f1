// Planar probes (kind planar): each frame, every planar probe whose plane faces the eye renders
// the scene from the camera mirrored in its plane with the renderer's own passes (depth prepass,
// shadows, G-buffer, lighting) and probes.capture_bounce, through an oblique near plane at the
// mirror (nothing on or behind it is drawn), then probes.planar_store writes its layer of the
// planar array (radiance and reflected distance) and probes.planar_mips its box mips, which a
// glossy reflection reads at its cone's footprint (planar.glsl).
#include "module_impl.hpp"

#include "speculum/core.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace speculum::probes {
namespace {

constexpr VkFormat kPlanarFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
// The oblique near plane lies this far in front of the mirror: exactly on it, depth precision
// lets the mirror's own triangles through in speckles; 2 mm hides no object that stands on it.
constexpr float kClipOffset = 0.002f;
// A pixel is on the plane when its normal is within acos(0.95) = 18 degrees of the plane's (a
// normal map's bumps) and its position within 1 cm (plus 0.2% of its distance, planar.glsl).
constexpr float kNormalTolerance = 0.95f;
constexpr float kDistanceTolerance = 0.01f;

struct StorePush {
    glm::mat4 invViewProj;
    glm::vec4 eye;
    glm::vec4 plane;
    glm::vec4 axisX, axisZ;  // the rectangle's axes over its half extents, with their offsets
};
static_assert(sizeof(StorePush) == 128, "lavapipe's push constant limit");

// The planar image's height for a view `viewHeight` tall: the probe's resolution, or half the view's.
uint32_t planarHeight(const PlanarInfo& p, uint32_t viewHeight) {
    return p.probe.resolution > 0 ? p.probe.resolution : std::max(viewHeight / 2, 1u);
}

}  // namespace

PlanarInfo describePlanar(const Scene& scene, int node) {
    const Node& n = scene.nodes.at(size_t(node));
    PlanarInfo info;
    info.node = node;
    info.name = probeName(scene, node);
    info.probe = n.probe.value_or(ReflectionProbe{});
    info.origin = glm::vec3(n.world[3]);
    info.normal = glm::normalize(glm::vec3(n.world[1]));
    glm::vec3 x = glm::vec3(n.world[0]);
    x -= glm::dot(x, info.normal) * info.normal;
    info.axisX = glm::normalize(x);
    info.axisZ = glm::cross(info.axisX, info.normal);
    info.plane = glm::vec4(info.normal, -glm::dot(info.normal, info.origin));
    return info;
}

glm::mat4 reflectionMatrix(glm::vec4 plane) {
    const glm::vec3 n(plane);
    glm::mat4 m(1.0f);
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) m[c][r] -= 2.0f * n[c] * n[r];
    m[3] = glm::vec4(-2.0f * plane.w * n, 1.0f);
    return m;
}

bool mirroredCamera(const render::CameraState& view, glm::vec4 plane, uint32_t width, uint32_t height,
                    float clipOffset, render::CameraState& out) {
    // Only the reversed-Z infinite perspective (renderer.hpp) has the w row -z this derivation needs.
    if (view.proj[2][3] != -1.0f || view.proj[3][3] != 0.0f) return false;
    const glm::vec3 n(plane);
    if (glm::dot(n, view.position) + plane.w <= clipOffset) return false;
    render::CameraState c = view;
    const glm::dmat4 mirror(reflectionMatrix(plane));
    const glm::dmat4 v = glm::dmat4(view.view) * mirror;
    // The clip plane (visible side positive) in the mirrored camera's space. The mirrored view
    // is a rigid map times a reflection, so its inverse transpose keeps the normal unit.
    const glm::dvec4 clip = glm::transpose(glm::inverse(v)) * glm::dvec4(glm::dvec3(n), double(plane.w) - clipOffset);
    // Reversed-Z: clip.z = znear and clip.w = -z. With row z replaced by row w - a * C, the near
    // test z <= w becomes a * C.y >= 0 (the visible side), and the far test z >= 0 becomes
    // a * C.y <= -y.z. C.y is at most |y|, and -y.z is |y| cos(theta) with theta the angle to the
    // axis, so a = cos of the frustum's widest half-angle keeps every visible point; depth
    // 1 - a C.y / -y.z still falls along every ray (reversed-Z ordering holds).
    const double tx = 1.0 / std::abs(double(view.proj[0][0])), ty = 1.0 / std::abs(double(view.proj[1][1]));
    const double a = 1.0 / std::sqrt(1.0 + tx * tx + ty * ty);
    glm::dmat4 p(view.proj);
    for (int col = 0; col < 4; ++col) p[col][2] = p[col][3] - a * clip[col];
    c.view = glm::mat4(v);
    c.proj = glm::mat4(p);
    c.viewProj = glm::mat4(p * v);
    c.invViewProj = glm::mat4(glm::inverse(p * v));
    c.position = glm::vec3(mirror * glm::dvec4(glm::dvec3(view.position), 1.0));
    c.width = std::max(width, 1u);
    c.height = std::max(height, 1u);
    out = c;
    return true;
}

void Probes::Impl::createPlanar() {
    const Scene& scene = renderer.scene();
    for (int i : activeProbeNodes(scene, ProbeKind::Planar)) planar.list.push_back(describePlanar(scene, i));
    validatePlanar();
    planar.records = gpu::Buffer(ctx, sizeof(shader::PlanarProbe) * kMaxPlanarProbes,
                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "probes.planar.records");
    planar.store = gpu::createComputePipeline(ctx, "probes/planar_store.comp", sizeof(StorePush), "probes.planar_store");
    allocatePlanar(4, 4);
}

void Probes::Impl::validatePlanar() const {
    const std::string file = renderer.scene().path.string();
    if (planar.list.size() > kMaxPlanarProbes)
        throw inputError(file, planar.list[kMaxPlanarProbes].name + ".extensions.SPECULUM_reflection_probe: " +
                                   std::to_string(planar.list.size()) + " planar probes; a scene holds at most " +
                                   std::to_string(kMaxPlanarProbes) +
                                   " (each renders the scene again every frame): this one is one too many");
    const uint32_t limit = ctx.properties().limits.maxImageDimension2D;
    for (const PlanarInfo& p : planar.list)
        if (p.probe.resolution > limit)
            throw inputError(file, p.name + ".extensions.SPECULUM_reflection_probe.resolution: " +
                                       std::to_string(p.probe.resolution) + " exceeds the device's 2D image limit of " +
                                       std::to_string(limit) + " (" + ctx.deviceName() + ")");
}

void Probes::Impl::allocatePlanar(uint32_t width, uint32_t height) {
    PlanarState& s = planar;
    s.width = width;
    s.height = height;
    s.valid = false;  // new images: the next renderPlanar renders whatever its interval
    uint32_t h = 4;
    for (const PlanarInfo& p : s.list) h = std::max(h, planarHeight(p, height));
    const uint32_t limit = ctx.properties().limits.maxImageDimension2D;
    h = std::min(h, limit);
    // The view's aspect: the mirrored camera keeps the view's projection.
    const uint32_t w = std::clamp(uint32_t(std::lround(double(h) * width / std::max(height, 1u))), 1u, limit);
    const uint32_t mips = std::max(1, int(std::bit_width(std::min(w, h))) - 2);  // down to about 4 px
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                    VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    s.images = gpu::Image(ctx, {w, h, kPlanarFormat, mips, uint32_t(std::max<size_t>(s.list.size(), 1)), false, usage},
                          "probes.planar");
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        gpu::transition(cmd, s.images.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
        VkClearColorValue zero{};
        VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
        vkCmdClearColorImage(cmd, s.images.get(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &all);
    });
}

void Probes::Impl::renderPlanarProbe(size_t index, const render::FrameInputs& view, uint32_t base) {
    PlanarState& s = planar;
    const PlanarInfo& info = s.list[index];
    const uint32_t w = view.camera.width, h = view.camera.height;
    const uint32_t layer = uint32_t(index);
    FrameGraph fg(FrameGraphConfig{w, h});
    CaptureFace cap = addCaptureView(fg, view, true);
    TextureHandle images = fg.importTexture("probes.planar", descOf(s.images),
                                            {s.images.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                                             s.images.desc().usage});
    struct Store {
        TextureHandle depth, face, out;
    };
    const Subresource target{base, 1, layer, 1};
    const auto& st = fg.addPass<Store>(
        "probes.planar_store", PassType::Compute,
        [&](PassBuilder& pb, Store& d) {
            d.depth = pb.read(cap.g.depth, TextureUsage::Sampled);
            d.face = pb.read(cap.face, TextureUsage::Sampled);
            d.out = pb.write(images, TextureUsage::StorageWrite, target);
        },
        [this, &s, cam = view.camera, &info, target, &env = renderer.environment()](const Store& d, PassContext& pc) {
            s.store.bind(pc.cmd());
            gpu::DescriptorWriter()
                .sampled("depthTex", pc.view(d.depth), nearest)
                .sampled("faceTex", pc.view(d.face), nearest)
                .sampled("envSpecular", env.specular().view(), env.sampler())
                .storage("outImage", pc.view(d.out, target, VK_IMAGE_VIEW_TYPE_2D))
                .push(ctx, pc.cmd(), s.store);
            const glm::vec3 x = info.axisX / info.probe.extents.x, z = info.axisZ / info.probe.extents.y;
            StorePush p{cam.invViewProj, glm::vec4(cam.position, 0.0f), info.plane,
                        glm::vec4(x, -glm::dot(x, info.origin)), glm::vec4(z, -glm::dot(z, info.origin))};
            vkCmdPushConstants(pc.cmd(), s.store.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(p), &p);
            vkCmdDispatch(pc.cmd(), (cam.width + 7) / 8, (cam.height + 7) / 8, 1);
        });
    TextureHandle last = st.out;
    // Box mips for glossy lobes: each level a linear blit of the one above (one pass per level,
    // so the graph orders them).
    struct Mip {
        TextureHandle src, dst;
    };
    for (uint32_t m = base + 1; m < s.images.desc().mips; ++m) {
        const auto& mp = fg.addPass<Mip>(
            "probes.planar_mips." + std::to_string(m), PassType::Transfer,
            [&](PassBuilder& pb, Mip& d) {
                d.src = pb.read(last, TextureUsage::TransferSrc, Subresource{m - 1, 1, layer, 1});
                d.dst = pb.write(last, TextureUsage::TransferDst, Subresource{m, 1, layer, 1});
            },
            [m, layer, w0 = s.images.desc().width, h0 = s.images.desc().height](const Mip& d, PassContext& pc) {
                auto size = [&](uint32_t mip) {
                    return VkOffset3D{int32_t(std::max(w0 >> mip, 1u)), int32_t(std::max(h0 >> mip, 1u)), 1};
                };
                VkImageBlit blit{};
                blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, m - 1, layer, 1};
                blit.srcOffsets[1] = size(m - 1);
                blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, m, layer, 1};
                blit.dstOffsets[1] = size(m);
                vkCmdBlitImage(pc.cmd(), pc.image(d.src), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pc.image(d.dst),
                               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
            });
        last = mp.dst;
    }
    fg.markOutput(last);
    s.ms += runCapture(fg);
}

void Probes::renderPlanar(const render::FrameInputs& view, int interval) {
    Impl& m = *impl_;
    Impl::PlanarState& s = m.planar;
    s.ms = 0.0;
    if (s.list.empty()) return;
    const render::CameraState& cam = view.camera;
    if (cam.width != s.width || cam.height != s.height) m.allocatePlanar(cam.width, cam.height);
    if (s.valid && ++s.sinceRender < interval) return;
    s.sinceRender = 0;
    s.valid = true;
    s.rendered = 0;
    const gpu::ImageDesc& d = s.images.desc();
    auto* out = static_cast<shader::PlanarProbe*>(s.records.mapped());
    for (size_t i = 0; i < s.list.size(); ++i) {
        const PlanarInfo& info = s.list[i];
        // A probe below the array's height renders at the mip nearest its own.
        const double ratio = double(d.height) / double(planarHeight(info, cam.height));
        const uint32_t base = std::min(uint32_t(std::max(0L, std::lround(std::log2(ratio)))), d.mips - 1);
        const uint32_t w = std::max(d.width >> base, 1u), h = std::max(d.height >> base, 1u);
        render::FrameInputs mirrored;
        if (!mirroredCamera(cam, info.plane, w, h, kClipOffset, mirrored.camera)) continue;
        mirrored.previousCamera = mirrored.camera;
        mirrored.primaryView = view.primaryView;
        mirrored.mirrored = true;
        m.renderPlanarProbe(i, mirrored, base);
        shader::PlanarProbe rec{};
        rec.viewProj = mirrored.camera.viewProj;
        rec.worldToPlane = glm::inverse(glm::mat4(glm::vec4(info.axisX, 0.0f), glm::vec4(info.normal, 0.0f),
                                                  glm::vec4(info.axisZ, 0.0f), glm::vec4(info.origin, 1.0f)));
        rec.plane = info.plane;
        rec.extents = glm::vec4(info.probe.extents.x, info.probe.extents.y, kNormalTolerance, kDistanceTolerance);
        const float tanHalf = 1.0f / std::abs(cam.proj[1][1]);
        rec.params = glm::vec4(float(i), float(base), 2.0f * tanHalf / float(h), float(d.mips - 1));
        out[s.rendered++] = rec;
    }
}

const std::vector<PlanarInfo>& Probes::planars() const { return impl_->planar.list; }
double Probes::planarMs() const { return impl_->planar.ms; }

}  // namespace speculum::probes
