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

struct GroundPush {
    glm::mat4 invViewProj;
    glm::vec4 plane;
    glm::vec4 params;  // x the normal tolerance's cosine
    glm::uvec4 info;   // xy size, z 1: a shadow mask
};
static_assert(sizeof(GroundPush) == 112, "lavapipe's push constant limit");

// The ground's orthographic camera stands this far above the plane. render.lighting takes an
// orthographic view's v along its rays (the normal); probes.capture_bounce takes it from this
// eye, within 5 degrees of the normal over an 8 m rectangle. Its depth range is the plane +-2 cm: the plane's triangles within the planar probe's 1 cm
// tolerance are drawn, and of an object standing on it only what lies in that slab (a sphere's
// bottom, 15 cm across for a 60 cm radius, which the normal test then leaves out).
constexpr float kGroundHeight = 50.0f;
constexpr float kGroundSlab = 0.02f;

// The planar image's height for a view `viewHeight` tall: the probe's resolution, or
// probes.planar_scale of the view's (half by default).
uint32_t planarHeight(const PlanarInfo& p, uint32_t viewHeight, float scale) {
    return p.probe.resolution > 0 ? p.probe.resolution
                                  : std::max(uint32_t(std::lround(double(viewHeight) * double(scale))), 1u);
}

// Box mips for glossy lobes below mip `first` of `layer`: each level a linear blit of the one
// above (one pass per level, so the graph orders them). Returns the last level's handle.
TextureHandle addBoxMips(FrameGraph& fg, TextureHandle image, const std::string& name, uint32_t layer, uint32_t first,
                         const gpu::ImageDesc& desc) {
    struct Mip {
        TextureHandle src, dst;
    };
    TextureHandle last = image;
    for (uint32_t m = first + 1; m < desc.mips; ++m) {
        const auto& mp = fg.addPass<Mip>(
            name + "." + std::to_string(m), PassType::Transfer,
            [&](PassBuilder& pb, Mip& d) {
                d.src = pb.read(last, TextureUsage::TransferSrc, Subresource{m - 1, 1, layer, 1});
                d.dst = pb.write(last, TextureUsage::TransferDst, Subresource{m, 1, layer, 1});
            },
            [m, layer, w0 = desc.width, h0 = desc.height](const Mip& d, PassContext& pc) {
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
    return last;
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

TexelRect planarFootprint(const glm::mat4& viewProj, const PlanarInfo& info, uint32_t width, uint32_t height,
                          uint32_t margin) {
    const glm::dmat4 vp(viewProj);
    const glm::dvec3 o(info.origin), x(info.axisX * info.probe.extents.x), z(info.axisZ * info.probe.extents.y);
    const glm::dvec4 corners[4] = {vp * glm::dvec4(o - x - z, 1.0), vp * glm::dvec4(o + x - z, 1.0),
                                   vp * glm::dvec4(o + x + z, 1.0), vp * glm::dvec4(o - x + z, 1.0)};
    // Clipped at the near plane (reversed-Z: z <= w in front of it; there w >= znear > 0), so
    // a floor running under the camera projects to the screen's edge, not through infinity. The
    // clipped polygon's points widen the bounds as they come.
    glm::dvec2 lo(1e30), hi(-1e30);
    bool any = false;
    auto add = [&](const glm::dvec4& c) {
        const glm::dvec2 uv = glm::dvec2(c) / std::max(c.w, 1e-12) * 0.5 + 0.5;
        lo = glm::min(lo, uv);
        hi = glm::max(hi, uv);
        any = true;
    };
    for (size_t i = 0; i < 4; ++i) {
        const glm::dvec4 &a = corners[i], &b = corners[(i + 1) % 4];
        const double fa = a.w - a.z, fb = b.w - b.z;
        if (fa >= 0.0) add(a);
        if ((fa >= 0.0) != (fb >= 0.0)) add(a + (b - a) * (fa / (fa - fb)));
    }
    if (!any) return {};
    const glm::dvec2 size(width, height), m(margin);
    const glm::dvec2 a = glm::clamp(glm::floor(lo * size) - m, glm::dvec2(0.0), size);
    const glm::dvec2 b = glm::clamp(glm::ceil(hi * size) + m, glm::dvec2(0.0), size);
    if (a.x >= b.x || a.y >= b.y) return {};
    return {uint32_t(a.x), uint32_t(a.y), uint32_t(b.x), uint32_t(b.y)};
}

render::CameraState cropCamera(const render::CameraState& camera, const TexelRect& rect) {
    if (rect.x0 == 0 && rect.y0 == 0 && rect.x1 == camera.width && rect.y1 == camera.height) return camera;
    // NDC of the rect's edges in the full image, and the window that maps them to [-1, 1]:
    // x' = (x - c w) / s on clip coordinates, rows 0 and 1 only (depth and w keep their rows).
    const glm::dvec2 size(camera.width, camera.height);
    const glm::dvec2 lo = glm::dvec2(rect.x0, rect.y0) / size * 2.0 - 1.0, hi = glm::dvec2(rect.x1, rect.y1) / size * 2.0 - 1.0;
    const glm::dvec2 c = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
    glm::dmat4 window(1.0);
    window[0][0] = 1.0 / half.x;
    window[1][1] = 1.0 / half.y;
    window[3][0] = -c.x / half.x;
    window[3][1] = -c.y / half.y;
    render::CameraState out = camera;
    out.proj = glm::mat4(window * glm::dmat4(camera.proj));
    const glm::dmat4 viewProj = window * glm::dmat4(camera.proj) * glm::dmat4(camera.view);
    out.viewProj = glm::mat4(viewProj);
    out.invViewProj = glm::mat4(glm::inverse(viewProj));
    out.width = rect.x1 - rect.x0;
    out.height = rect.y1 - rect.y0;
    return out;
}

void Probes::Impl::createPlanar() {
    const Scene& scene = renderer.scene();
    for (int i : activeProbeNodes(scene, ProbeKind::Planar)) planar.list.push_back(describePlanar(scene, i));
    validatePlanar();
    planar.records = gpu::Buffer(ctx, sizeof(shader::PlanarProbe) * kMaxPlanarProbes,
                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "probes.planar.records");
    planar.store = gpu::createComputePipeline(ctx, "probes/planar_store.comp", sizeof(StorePush), "probes.planar_store");
    allocatePlanar(4, 4);
    createGrounds();
}

void Probes::Impl::createGrounds() {
    PlanarState& s = planar;
    // Without planar probes or with probes.planar_ground 0, one black texel: capture_bounce
    // binds the array whatever the count.
    const bool any = !s.list.empty() && settings.planarGround > 0;
    const uint32_t size = any ? std::min(uint32_t(settings.planarGround), ctx.properties().limits.maxImageDimension2D) : 1u;
    const uint32_t mips = std::max(1, int(std::bit_width(size)) - 2);  // down to about 4 px
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                    VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    s.ground = gpu::Image(ctx, {size, size, kPlanarFormat, mips, uint32_t(any ? s.list.size() : 1), false, usage},
                          "probes.planar_ground");
    s.groundRecords = gpu::Buffer(ctx, sizeof(shader::PlanarGround) * kMaxPlanarProbes,
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "probes.ground_records");
    // The scene's lights (ids 0-287): the store takes out the view's direct specular.
    s.groundStore = gpu::createComputePipeline(ctx, "probes/ground_store.comp", sizeof(GroundPush), "probes.ground_store",
                                               renderer.lightingConstants());
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        gpu::transition(cmd, s.ground.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
        VkClearColorValue zero{};
        VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
        vkCmdClearColorImage(cmd, s.ground.get(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &all);
    });
}

render::CameraState groundCamera(const PlanarInfo& info, uint32_t size) {
    Camera c;
    c.perspective = false;
    c.xmag = info.probe.extents.x;
    c.ymag = info.probe.extents.y;
    c.znear = kGroundHeight - kGroundSlab;
    c.zfar = kGroundHeight + kGroundSlab;
    // Looking down the normal (-Z = -normal), the image's up along the rectangle's depth axis:
    // X = Y x Z = axisZ x normal = -axisX, so xmag spans the width and ymag the depth.
    c.world = glm::mat4(glm::vec4(-info.axisX, 0.0f), glm::vec4(info.axisZ, 0.0f), glm::vec4(info.normal, 0.0f),
                        glm::vec4(info.origin + info.normal * kGroundHeight, 1.0f));
    return render::makeCamera(c, size, size);
}

void Probes::Impl::renderGrounds() {
    PlanarState& s = planar;
    s.groundValid = true;
    if (s.list.empty() || settings.planarGround <= 0) return;
    // The grounds' own surfaces reflect without them (a floor's ray goes up, and nothing else
    // is in the slab), and the graph below writes what capture_bounce would read.
    s.groundCount = 0;
    const gpu::ImageDesc& desc = s.ground.desc();
    auto* out = static_cast<shader::PlanarGround*>(s.groundRecords.mapped());
    for (size_t i = 0; i < s.list.size(); ++i) {
        const PlanarInfo& info = s.list[i];
        const uint32_t layer = uint32_t(i);
        FrameGraph fg(FrameGraphConfig{desc.width, desc.height});
        render::FrameInputs frame;
        frame.camera = frame.previousCamera = groundCamera(info, desc.width);
        CaptureFace cap = addCaptureView(fg, frame);
        struct Store {
            render::GBuffer g;
            TextureHandle face, out;
        };
        const Subresource target{0, 1, layer, 1};
        const auto& st = fg.addPass<Store>(
            "probes.ground_store", PassType::Compute,
            [&](PassBuilder& pb, Store& d) {
                d.g = render::readSurfaceAttachments(pb, cap.g);
                if (cap.g.shadowMask.valid()) d.g.shadowMask = pb.read(cap.g.shadowMask, TextureUsage::Sampled);
                d.face = pb.read(cap.face, TextureUsage::Sampled);
                d.out = pb.write(cap.ground, TextureUsage::StorageWrite, target);
            },
            [this, &s, &info, target, size = desc.width, cam = frame.camera](const Store& d, PassContext& pc) {
                s.groundStore.bind(pc.cmd());
                const bool shadowed = d.g.shadowMask.valid();
                // No shadowed light: the face stands in for the mask's binding, unread.
                gpu::DescriptorWriter()
                    .sampled("depthTex", pc.view(d.g.depth), nearest)
                    .sampled("albedoTex", pc.view(d.g.albedo), nearest)
                    .sampled("normalTex", pc.view(d.g.normal), nearest)
                    .sampled("faceTex", pc.view(d.face), nearest)
                    .sampled("shadowMask", shadowed ? pc.view(d.g.shadowMask) : pc.view(d.face), nearest)
                    .storage("outImage", pc.view(d.out, target, VK_IMAGE_VIEW_TYPE_2D))
                    .push(ctx, pc.cmd(), s.groundStore);
                GroundPush p{cam.invViewProj, info.plane, glm::vec4(kNormalTolerance, 0.0f, 0.0f, 0.0f),
                             glm::uvec4(size, size, shadowed ? 1u : 0u, 0u)};
                vkCmdPushConstants(pc.cmd(), s.groundStore.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(p), &p);
                vkCmdDispatch(pc.cmd(), (size + 7) / 8, (size + 7) / 8, 1);
            });
        fg.markOutput(addBoxMips(fg, st.out, "probes.ground_mips", layer, 0, desc));
        ms += runCapture(fg);
        const float texel = 2.0f * std::max(info.probe.extents.x, info.probe.extents.y) / float(desc.width);
        out[i] = shader::PlanarGround{frame.camera.viewProj, info.plane,
                                      glm::vec4(float(layer), texel, float(desc.mips - 1), 0.0f)};
    }
    s.groundCount = uint32_t(s.list.size());
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
    for (const PlanarInfo& p : s.list) h = std::max(h, planarHeight(p, height, settings.planarScale));
    // At most 4096: planar_store takes the crop's offset as x + 4096 y in a float.
    const uint32_t limit = std::min(ctx.properties().limits.maxImageDimension2D, 4096u);
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

void Probes::Impl::renderPlanarProbe(size_t index, const render::FrameInputs& view, uint32_t base, const TexelRect& rect) {
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
        [this, &s, cam = view.camera, &info, target, rect, &env = renderer.environment()](const Store& d, PassContext& pc) {
            s.store.bind(pc.cmd());
            gpu::DescriptorWriter()
                .sampled("depthTex", pc.view(d.depth), nearest)
                .sampled("faceTex", pc.view(d.face), nearest)
                .sampled("envSpecular", env.specular().view(), env.sampler())
                .storage("outImage", pc.view(d.out, target, VK_IMAGE_VIEW_TYPE_2D))
                .push(ctx, pc.cmd(), s.store);
            const glm::vec3 x = info.axisX / info.probe.extents.x, z = info.axisZ / info.probe.extents.y;
            // eye.w: where the crop's first texel lies in the layer, x + 4096 y (exact in a float:
            // allocatePlanar keeps the image within 4096 texels).
            StorePush p{cam.invViewProj, glm::vec4(cam.position, float(rect.x0 + 4096u * rect.y0)), info.plane,
                        glm::vec4(x, -glm::dot(x, info.origin)), glm::vec4(z, -glm::dot(z, info.origin))};
            vkCmdPushConstants(pc.cmd(), s.store.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(p), &p);
            vkCmdDispatch(pc.cmd(), (cam.width + 7) / 8, (cam.height + 7) / 8, 1);
        });
    TextureHandle last = addBoxMips(fg, st.out, "probes.planar_mips", layer, base, s.images.desc());
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
        const double ratio = double(d.height) / double(planarHeight(info, cam.height, m.settings.planarScale));
        const uint32_t base = std::min(uint32_t(std::max(0L, std::lround(std::log2(ratio)))), d.mips - 1);
        const uint32_t w = std::max(d.width >> base, 1u), h = std::max(d.height >> base, 1u);
        // Only what its rectangle covers on screen: a mirror a tenth of the view costs a tenth
        // of the view; one off screen, nothing. Texel for texel the image holds what the whole
        // mirrored view would (cropCamera keeps each texel's ray), the rest of the layer is stale.
        const TexelRect rect = m.settings.planarCrop ? planarFootprint(cam.viewProj, info, w, h, kPlanarCropMargin)
                                                     : TexelRect{0, 0, w, h};
        render::FrameInputs mirrored;
        render::CameraState full;
        if (rect.empty() || !mirroredCamera(cam, info.plane, w, h, kClipOffset, full)) continue;
        mirrored.camera = mirrored.previousCamera = cropCamera(full, rect);
        // A reflection, like a probe's capture: what the player's view leaves out
        // (Node::hiddenPrimary, the game's gems, seen only in mirrors) is drawn into it.
        mirrored.primaryView = false;
        mirrored.mirrored = true;
        m.renderPlanarProbe(i, mirrored, base, rect);
        shader::PlanarProbe rec{};
        rec.viewProj = full.viewProj;
        rec.worldToPlane = glm::inverse(glm::mat4(glm::vec4(info.axisX, 0.0f), glm::vec4(info.normal, 0.0f),
                                                  glm::vec4(info.axisZ, 0.0f), glm::vec4(info.origin, 1.0f)));
        rec.plane = info.plane;
        rec.extents = glm::vec4(info.probe.extents.x, info.probe.extents.y, kNormalTolerance, kDistanceTolerance);
        const float tanHalf = 1.0f / std::abs(cam.proj[1][1]);
        rec.params = glm::vec4(float(i), float(base), 2.0f * tanHalf / float(h), float(d.mips - 1));
        rec.crop = glm::vec4((float(rect.x0) + 0.5f) / float(w), (float(rect.y0) + 0.5f) / float(h),
                             (float(rect.x1) - 0.5f) / float(w), (float(rect.y1) - 0.5f) / float(h));
        out[s.rendered++] = rec;
    }
}

const std::vector<PlanarInfo>& Probes::planars() const { return impl_->planar.list; }
double Probes::planarMs() const { return impl_->planar.ms; }

}  // namespace speculum::probes
