// The reflections module on lavapipe: the Hi-Z pyramid against a CPU min/max of the same
// depth, both tracers against CPU ray-box intersections on an analytic scene, and no NaN, Inf
// or negative radiance in `reflection` on every scene, camera and test size.
#include "render_test_support.hpp"

#include "speculum/app/frame_runner.hpp"
#include "speculum/chain.hpp"
#include "speculum/reflections/math.hpp"
#include "speculum/reflections/reflections.hpp"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>

using namespace speculum;
namespace fs = std::filesystem;

namespace {

struct Readback {
    std::vector<std::vector<reflections::MinMax>> hiz;  // per level
    std::vector<glm::vec4> hit;    // at the trace's size
    std::vector<glm::vec4> guide;  // half resolution only
    app::FrameResult result;
};

// Renders one frame with the module and copies every Hi-Z level and the hit image out.
Readback renderWithModule(const gpu::Context& ctx, render::Renderer& renderer, reflections::Reflections& module,
                          const reflections::ReflectionSettings& s, const render::CameraState& camera,
                          const std::vector<std::string>& aovs,
                          const std::optional<render::CameraState>& previous = std::nullopt) {
    uint32_t w = camera.width, h = camera.height, levels = reflections::pyramidLevels(w, h);
    std::vector<gpu::Buffer> hizBuffers;
    for (uint32_t l = 0; l < levels; ++l)
        hizBuffers.emplace_back(ctx, VkDeviceSize(reflections::levelSize(w, l)) * reflections::levelSize(h, l) * 8,
                                VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, "test.hiz");
    gpu::Buffer hitBuffer(ctx, VkDeviceSize(w) * h * 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, "test.hit");
    const bool half = s.resolution == reflections::Resolution::Half;
    const uint32_t hw = half ? (w + 1) / 2 : w, hh = half ? (h + 1) / 2 : h;
    gpu::Buffer guideBuffer(ctx, VkDeviceSize(hw) * hh * 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, "test.guide");
    render::FrameInputs frame{camera, previous.value_or(camera)};
    app::LitHook hook;
    hook.modules = {reflections::moduleInfo()};
    hook.moduleSpecular = true;
    hook.addPasses = [&](FrameGraph& fg, const render::GBuffer& g, TextureHandle lit, app::ModuleAovs& m) {
        reflections::ReflectionOutputs out = module.addPasses(fg, {g, lit, frame}, s);
        m.provided["reflection"] = {out.reflection, 3};
        m.provided["method"] = {out.method, 3};
        struct Data {
            TextureHandle hiz, hit, guide;
        };
        fg.addPass<Data>(
            "test.readback", PassType::Transfer,
            [&](PassBuilder& b, Data& d) {
                d.hiz = b.read(out.hiz, TextureUsage::TransferSrc);
                d.hit = b.read(out.hit, TextureUsage::TransferSrc);
                if (out.guide.valid()) d.guide = b.read(out.guide, TextureUsage::TransferSrc);
                b.sideEffect();
            },
            [&, levels](const Data& d, PassContext& pc) {
                for (uint32_t l = 0; l < levels; ++l) {
                    VkBufferImageCopy c{};
                    c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, l, 0, 1};
                    c.imageExtent = {reflections::levelSize(w, l), reflections::levelSize(h, l), 1};
                    vkCmdCopyImageToBuffer(pc.cmd(), pc.image(d.hiz), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                           hizBuffers[l].get(), 1, &c);
                }
                VkBufferImageCopy c{};
                c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                c.imageExtent = {hw, hh, 1};
                vkCmdCopyImageToBuffer(pc.cmd(), pc.image(d.hit), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, hitBuffer.get(),
                                       1, &c);
                if (d.guide.valid())
                    vkCmdCopyImageToBuffer(pc.cmd(), pc.image(d.guide), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                           guideBuffer.get(), 1, &c);
            });
        return out.lit;
    };
    app::FrameRunner runner(ctx, renderer, w, h);
    Readback r;
    r.result = runner.render(frame, aovs, hook);
    for (uint32_t l = 0; l < levels; ++l) {
        size_t n = size_t(reflections::levelSize(w, l)) * reflections::levelSize(h, l);
        std::vector<reflections::MinMax> level(n);
        std::memcpy(level.data(), hizBuffers[l].mapped(), n * sizeof(reflections::MinMax));
        r.hiz.push_back(std::move(level));
    }
    r.hit.resize(size_t(hw) * hh);
    std::memcpy(r.hit.data(), hitBuffer.mapped(), r.hit.size() * sizeof(glm::vec4));
    if (half) {
        r.guide.resize(size_t(hw) * hh);
        std::memcpy(r.guide.data(), guideBuffer.mapped(), r.guide.size() * sizeof(glm::vec4));
    }
    return r;
}

fs::path assetPath(const std::string& rel) {
    return fs::path(SPECULUM_SOURCE_DIR) / rel;
}

}  // namespace

class ReflectionsGpu : public render::test::SharedContextTest<ReflectionsGpu> {};

TEST_F(ReflectionsGpu, HiZEqualsCpuMinMaxAtOddAndEvenSizes) {
    Scene scene = loadScene(assetPath("assets/scenes/gallery.gltf"));
    render::Renderer renderer(*ctx_, scene);
    reflections::Reflections module(*ctx_, renderer);
    for (auto [w, h] : {std::pair{317u, 181u}, std::pair{640u, 360u}}) {
        render::CameraState cam = render::makeCamera(*scene.findCamera("main"), w, h);
        Readback r = renderWithModule(*ctx_, renderer, module, {}, cam, {"depth"});
        const app::AovImage& depthAov = r.result.aovs.at("depth");
        std::vector<float> depth(size_t(w) * h);
        for (size_t i = 0; i < depth.size(); ++i) depth[i] = depthAov.rgba[i * 4];
        auto cpu = reflections::buildHiZ(depth, w, h);
        ASSERT_EQ(cpu.size(), r.hiz.size());
        for (size_t l = 0; l < cpu.size(); ++l)
            for (size_t i = 0; i < cpu[l].size(); ++i) {
                ASSERT_EQ(r.hiz[l][i].farthest, cpu[l][i].farthest) << w << "x" << h << " level " << l << " cell " << i;
                ASSERT_EQ(r.hiz[l][i].closest, cpu[l][i].closest) << w << "x" << h << " level " << l << " cell " << i;
            }
    }
}

namespace {

struct Box {
    glm::vec3 lo, hi;
};

// Slab test; returns the entry distance or -1.
float hitBox(const Box& b, glm::vec3 o, glm::vec3 d) {
    glm::vec3 inv = 1.0f / d;
    glm::vec3 t0 = (b.lo - o) * inv, t1 = (b.hi - o) * inv;
    glm::vec3 tn = glm::min(t0, t1), tf = glm::max(t0, t1);
    float enter = std::max(std::max(tn.x, tn.y), tn.z), exit = std::min(std::min(tf.x, tf.y), tf.z);
    return enter <= exit && enter > 1e-4f ? enter : -1.0f;
}

// The analytic scene: a mirror floor (y = 0, |x|, |z| < 10), three cubes on it and a wall at
// z = -8; everything but the floor is a matte box for the CPU.
struct Analytic {
    std::vector<Box> boxes{{{-1.7f, 0.0f, -2.5f}, {-0.7f, 1.0f, -1.5f}},
                           {{0.2f, 0.0f, -4.2f}, {1.6f, 1.4f, -2.8f}},
                           {{-0.1f, 0.0f, -1.3f}, {0.5f, 0.6f, -0.7f}},
                           {{-10.0f, -5.0f, -8.2f}, {10.0f, 15.0f, -8.0f}}};
    // First hit along the ray: distance, and whether it is the floor.
    float first(glm::vec3 o, glm::vec3 d, bool& floor) const {
        float best = -1.0f;
        floor = false;
        for (const Box& b : boxes) {
            float t = hitBox(b, o, d);
            if (t > 0.0f && (best < 0.0f || t < best)) best = t;
        }
        if (d.y < 0.0f) {
            float t = -o.y / d.y;
            glm::vec3 p = o + d * t;
            if (t > 1e-4f && std::abs(p.x) < 10.0f && std::abs(p.z) < 10.0f && (best < 0.0f || t < best)) {
                best = t;
                floor = true;
            }
        }
        return best;
    }
};

Scene analyticScene(const Analytic& a) {
    Scene scene;
    Material mirror;
    mirror.name = "mirror";
    mirror.metallic = 1.0f;
    mirror.roughness = 0.0f;
    mirror.reflections = MaterialReflections{};
    Material matte;
    matte.name = "matte";
    matte.baseColor = glm::vec4(0.7f, 0.5f, 0.3f, 1.0f);
    matte.metallic = 0.0f;
    matte.roughness = 0.8f;
    scene.materials = {mirror, matte};
    using render::test::square;
    render::test::addMesh(scene, square({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 10.0f, 0));
    for (const Box& b : a.boxes) {
        glm::vec3 c = (b.lo + b.hi) * 0.5f, e = (b.hi - b.lo) * 0.5f;
        // Cubes: one half-size; the wall is a square facing +z.
        if (e.z < 0.5f * e.x) {
            render::test::addMesh(scene, square({c.x, c.y, b.hi.z}, {1, 0, 0}, {0, 1, 0}, e.x, 1));
            continue;
        }
        float s = e.x;
        render::test::addMesh(scene, square(c + glm::vec3(s, 0, 0), {0, 1, 0}, {0, 0, 1}, s, 1));
        render::test::addMesh(scene, square(c - glm::vec3(s, 0, 0), {0, 0, 1}, {0, 1, 0}, s, 1));
        render::test::addMesh(scene, square(c + glm::vec3(0, s, 0), {0, 0, 1}, {1, 0, 0}, s, 1));
        render::test::addMesh(scene, square(c + glm::vec3(0, 0, s), {1, 0, 0}, {0, 1, 0}, s, 1));
        render::test::addMesh(scene, square(c - glm::vec3(0, 0, s), {0, 1, 0}, {1, 0, 0}, s, 1));
    }
    return scene;
}

}  // namespace

// Both tracers hit where a CPU ray-box intersection says, within 1 pixel, for at least 99% of
// the mirror rays whose true hit is on screen and visible from the camera.
TEST_F(ReflectionsGpu, TracersHitWhereCpuIntersectionSays) {
    Analytic a;
    Scene scene = analyticScene(a);
    render::Renderer renderer(*ctx_, scene);
    reflections::Reflections module(*ctx_, renderer);
    const uint32_t w = 400, h = 240;
    render::CameraState cam = render::makeCamera({0.3f, 1.4f, 3.0f}, {0.0f, 0.4f, -2.5f}, {0, 1, 0},
                                                 glm::radians(60.0f), w, h);
    for (auto mode : {reflections::TraceMode::HiZ, reflections::TraceMode::Linear}) {
        reflections::ReflectionSettings s;
        s.trace = mode;
        s.maxIterations = 256;
        Readback r = renderWithModule(*ctx_, renderer, module, s, cam, {});
        size_t checked = 0, good = 0;
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                glm::vec3 o, d;
                render::primaryRay(cam, float(x), float(y), o, d);
                bool floor = false;
                float t = a.first(o, d, floor);
                if (!floor) continue;
                glm::vec3 p = o + d * t;
                glm::vec3 rd = glm::reflect(d, glm::vec3(0, 1, 0));
                bool again = false;
                float tr = a.first(p, rd, again);
                if (tr <= 0.0f) continue;
                glm::vec3 hit = p + rd * tr;
                glm::vec4 clip = cam.viewProj * glm::vec4(hit, 1.0f);
                if (clip.w <= 0.0f) continue;
                glm::vec2 px = (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * glm::vec2(w, h);
                if (px.x < 1.0f || px.y < 1.0f || px.x > w - 1.0f || px.y > h - 1.0f) continue;
                // Visible: the camera's ray towards the hit meets nothing before it.
                glm::vec3 toHit = hit - cam.position;
                bool f2 = false;
                float tv = a.first(cam.position, glm::normalize(toHit), f2);
                if (std::abs(tv - glm::length(toHit)) > 1e-3f * glm::length(toHit)) continue;
                ++checked;
                glm::vec4 g = r.hit[size_t(y) * w + x];
                if (g.z > 0.0f && glm::distance(glm::vec2(g), px) <= 1.0f) ++good;
            }
        ASSERT_GT(checked, 5000u) << "the analytic view must show many on-screen reflections";
        double share = double(good) / double(checked);
        EXPECT_GE(share, 0.99) << (mode == reflections::TraceMode::HiZ ? "hiz" : "linear") << ": " << good << " of "
                               << checked << " mirror rays within 1 px";
    }
}

// `reflection` holds finite, non-negative radiance on every scene, camera and test size.
TEST_F(ReflectionsGpu, ReflectionIsFiniteAndNonNegativeEverywhere) {
    const std::pair<uint32_t, uint32_t> sizes[] = {{320, 180}, {317, 181}, {641, 359}, {400, 300}, {333, 187}};
    for (const char* name : {"gallery", "cornell_mirrors", "failure_cases"}) {
        Scene scene = loadScene(assetPath(std::string("assets/scenes/") + name + ".gltf"));
        render::Renderer renderer(*ctx_, scene);
        reflections::Reflections module(*ctx_, renderer);
        for (const Camera& camera : scene.cameras)
            for (auto [w, h] : sizes) {
                render::CameraState cam = render::makeCamera(camera, w, h);
                app::FrameResult res = renderWithModule(*ctx_, renderer, module, {}, cam, {"reflection"}).result;
                const app::AovImage& img = res.aovs.at("reflection");
                size_t bad = 0;
                for (float v : img.rgba) bad += !std::isfinite(v) || v < 0.0f;
                EXPECT_EQ(bad, 0u) << name << "/" << camera.name << " at " << w << "x" << h;
            }
    }
}

// reflections.guide against its rule computed on the CPU from the depth and the full-resolution
// method AOV (reflective where the weights sum to 1), at an odd size (the last row and column
// of 2x2 blocks are clamped): per half pixel, reflective pixels first, then the closest depth on
// even checkerboard squares and the farthest on odd ones, the first of equals; and the world
// position it stores is the chosen pixel's.
TEST_F(ReflectionsGpu, GuidePicksByItsRuleAtOddSizes) {
    Scene scene = loadScene(assetPath("assets/scenes/gallery.gltf"));
    render::Renderer renderer(*ctx_, scene);
    reflections::Reflections module(*ctx_, renderer);
    const uint32_t w = 317, h = 181, hw = (w + 1) / 2, hh = (h + 1) / 2;
    render::CameraState cam = render::makeCamera(*scene.findCamera("main"), w, h);
    Readback full = renderWithModule(*ctx_, renderer, module, {}, cam, {"depth", "method", "normal", "roughness"});
    reflections::ReflectionSettings s;
    s.resolution = reflections::Resolution::Half;
    Readback half = renderWithModule(*ctx_, renderer, module, s, cam, {});
    const auto& depth = full.result.aovs.at("depth").rgba;
    const auto& method = full.result.aovs.at("method").rgba;
    const auto& normals = full.result.aovs.at("normal").rgba;
    const auto& roughness = full.result.aovs.at("roughness").rgba;
    ASSERT_EQ(half.guide.size(), size_t(hw) * hh);
    int wrong = 0, reflectiveHalf = 0;
    for (uint32_t y = 0; y < hh; ++y)
        for (uint32_t x = 0; x < hw; ++x) {
            bool closest = ((x + y) & 1) == 0;
            int best = 0;
            float bestDepth = -1.0f;
            bool bestReflective = false;
            for (int i = 0; i < 4; ++i) {
                uint32_t px = std::min(2 * x + (i & 1), w - 1), py = std::min(2 * y + (i >> 1), h - 1);
                size_t k = (size_t(py) * w + px) * 4;
                float d = depth[k];
                bool reflective = d > 0.0f && method[k] + method[k + 1] + method[k + 2] > 0.5f;
                bool better = bestDepth < 0.0f || (reflective && !bestReflective) ||
                              (reflective == bestReflective && (closest ? d > bestDepth : d < bestDepth));
                if (better) {
                    best = i;
                    bestDepth = d;
                    bestReflective = reflective;
                }
            }
            const glm::vec4& g = half.guide[size_t(y) * hw + x];
            int index = (int(std::abs(g.w)) - 1) & 3;  // the low bits of packGuide()
            bool reflective = g.w > 0.0f;
            reflectiveHalf += reflective;
            if (index != best || reflective != bestReflective) {
                if (++wrong <= 5)
                    ADD_FAILURE() << "half pixel " << x << "," << y << ": guide index " << index << (reflective ? "+" : "-")
                                  << ", rule " << best << (bestReflective ? "+" : "-");
                continue;
            }
            if (bestDepth > 0.0f) {
                uint32_t px = std::min(2 * x + (best & 1), w - 1), py = std::min(2 * y + (best >> 1), h - 1);
                glm::vec2 uv((float(px) + 0.5f) / float(w), (float(py) + 0.5f) / float(h));
                glm::vec4 p = cam.invViewProj * glm::vec4(uv * 2.0f - 1.0f, bestDepth, 1.0f);
                glm::vec3 world = glm::vec3(p) / p.w;
                ASSERT_LT(glm::length(world - glm::vec3(g)), 1e-3f * (1.0f + glm::length(world))) << x << "," << y;
                // The packed normal (7-bit octahedral) and roughness (6 bits) of that pixel.
                uint32_t bits = uint32_t(std::abs(g.w)) - 1u;
                glm::vec2 f = glm::vec2(float((bits >> 8) & 127u), float((bits >> 15) & 127u)) / 127.0f * 2.0f - 1.0f;
                glm::vec3 n(f, 1.0f - std::abs(f.x) - std::abs(f.y));
                float t = std::clamp(-n.z, 0.0f, 1.0f);
                n.x += n.x >= 0.0f ? -t : t;
                n.y += n.y >= 0.0f ? -t : t;
                size_t k = (size_t(py) * w + px) * 4;
                glm::vec3 want = glm::normalize(glm::vec3(normals[k], normals[k + 1], normals[k + 2]));
                ASSERT_GT(glm::dot(glm::normalize(n), want), std::cos(glm::radians(2.0f))) << x << "," << y;
                ASSERT_NEAR(float((bits >> 2) & 63u) / 63.0f, roughness[k], 0.5f / 63.0f + 1e-3f) << x << "," << y;
            }
        }
    EXPECT_EQ(wrong, 0);
    EXPECT_GT(reflectiveHalf, int(hw * hh) / 4);  // the scene is mostly reflective
    EXPECT_EQ(gpu::Context::validationMessageCount(), 0);
}

// Temporal accumulation starts from scratch when a setting changes (issue 13: "reset on settings
// changes"). Two modules run in lockstep on a camera that slides a little every frame, one with
// temporal accumulation and one without; both feed their own un-accumulated reflection to the
// bounce loop, so that the accumulating one's raw reflection is the other's output. While
// accumulating the two outputs differ; on the frame where a setting changes (cone samples 8 ->
// 4 in both) the accumulating module must output exactly this frame's reflection.
TEST_F(ReflectionsGpu, TemporalHistoryResetsWhenASettingChanges) {
    Scene scene = loadScene(assetPath("assets/scenes/gallery.gltf"));
    render::Renderer renderer(*ctx_, scene);
    reflections::Reflections accumulating(*ctx_, renderer), plain(*ctx_, renderer);
    reflections::ReflectionSettings on, off;
    on.temporal = true;
    const uint32_t w = 160, h = 90;
    const Camera& named = *scene.findCamera("main");
    auto cameraAt = [&](int frame) {
        Camera c = named;
        c.world = glm::translate(glm::mat4(1.0f), glm::vec3(0.03f * float(frame), 0.0f, 0.0f)) * c.world;
        return render::makeCamera(c, w, h);
    };
    auto reflection = [](const Readback& r) { return r.result.aovs.at("reflection").rgba; };
    auto maxDiff = [](const std::vector<float>& a, const std::vector<float>& b) {
        float m = 0.0f;
        for (size_t i = 0; i < a.size(); i += 4)
            for (int c = 0; c < 3; ++c) m = std::max(m, std::abs(a[i + c] - b[i + c]));
        return m;
    };
    std::optional<render::CameraState> previous;
    float accumulatedDiff = 0.0f;
    for (int frame = 0; frame < 8; ++frame) {
        render::CameraState cam = cameraAt(frame);
        if (frame == 7) on.coneSamples = off.coneSamples = 4;  // the change
        auto a = reflection(renderWithModule(*ctx_, renderer, accumulating, on, cam, {"reflection"}, previous));
        auto b = reflection(renderWithModule(*ctx_, renderer, plain, off, cam, {"reflection"}, previous));
        if (frame == 6) accumulatedDiff = maxDiff(a, b);
        if (frame == 7) EXPECT_EQ(maxDiff(a, b), 0.0f) << "the history survived a settings change";
        previous = cam;
    }
    EXPECT_GT(accumulatedDiff, 0.01f) << "no accumulation before the change: the test would prove nothing";
    EXPECT_EQ(gpu::Context::validationMessageCount(), 0);
}
