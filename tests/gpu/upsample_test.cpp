// reflections.upsample alone, on synthetic images (issue 13): across a depth edge the joint
// bilateral upsampler takes nothing from the other side, and a constant image comes back as the
// constant. The guide is made on the CPU with the rule of modules/reflections/shaders/guide.glsl
// (checkerboard of the closest and the farthest of each 2x2).
#include "speculum/reflections/upsample.hpp"
#include "render_test_support.hpp"
#include "speculum/gpu/context.hpp"
#include "speculum/gpu/fg_executor.hpp"
#include "speculum/gpu/resources.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cstring>
#include <functional>

using namespace speculum;

namespace {

constexpr uint32_t W = 64, H = 40, LW = W / 2, LH = H / 2;

struct Images {
    std::vector<float> depth;     // W x H
    std::vector<glm::vec4> lowA;  // LW x LH
    std::vector<glm::vec4> lowB;
    std::vector<glm::vec4> guide;
};

// The guide of guide.glsl for a depth image where every pixel reflects.
std::vector<glm::vec4> makeGuide(const std::vector<float>& depth) {
    std::vector<glm::vec4> guide(LW * LH);
    for (uint32_t y = 0; y < LH; ++y)
        for (uint32_t x = 0; x < LW; ++x) {
            bool closest = ((x + y) & 1) == 0;
            uint32_t best = 0;
            float bestDepth = -1.0f;
            for (uint32_t i = 0; i < 4; ++i) {
                glm::uvec2 p{2 * x + (i & 1), 2 * y + (i >> 1)};
                float d = depth[p.y * W + p.x];
                if (bestDepth < 0.0f || (closest ? d > bestDepth : d < bestDepth)) {
                    best = i;
                    bestDepth = d;
                }
            }
            // World = (ndc, depth) under the identity matrix of upsample() below.
            glm::vec2 px{float(2 * x + (best & 1)) + 0.5f, float(2 * y + (best >> 1)) + 0.5f};
            // w: packGuide() of modules/reflections/shaders/guide.glsl for a reflective pixel with
            // roughness 0 and normal +z (octahedral 0.5, 0.5 -> 64 of 127).
            uint32_t bits = best | (0u << 2) | (64u << 8) | (64u << 15);
            guide[y * LW + x] = {px.x / W * 2.0f - 1.0f, px.y / H * 2.0f - 1.0f, bestDepth, float(1u + bits)};
        }
    return guide;
}

template <typename T>
std::span<const std::byte> bytes(const std::vector<T>& v) {
    return std::as_bytes(std::span(v));
}

// Runs the upsampler on the images and returns its two full-resolution outputs.
std::array<std::vector<float>, 2> upsample(gpu::Context& ctx, const Images& im) {
    auto image = [&](uint32_t w, uint32_t h, VkFormat f, std::span<const std::byte> data, const char* name) {
        gpu::Image img(ctx, {w, h, f, 1, 1, false, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT}, name);
        gpu::uploadImage(ctx, img, data, false);
        return img;
    };
    std::vector<glm::vec4> normals(W * H, glm::vec4(0, 0, 1, 0.0f));
    gpu::Image depth = image(W, H, VK_FORMAT_R32_SFLOAT, bytes(im.depth), "test.depth");
    gpu::Image normal = image(W, H, VK_FORMAT_R32G32B32A32_SFLOAT, bytes(normals), "test.normal");
    gpu::Image guide = image(LW, LH, VK_FORMAT_R32G32B32A32_SFLOAT, bytes(im.guide), "test.guide");
    gpu::Image lowA = image(LW, LH, VK_FORMAT_R32G32B32A32_SFLOAT, bytes(im.lowA), "test.low_a");
    gpu::Image lowB = image(LW, LH, VK_FORMAT_R32G32B32A32_SFLOAT, bytes(im.lowB), "test.low_b");
    reflections::BilateralUpsampler upsampler(ctx);
    gpu::Buffer readback(ctx, VkDeviceSize(W) * H * 8 * 2, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, "test.readback");

    FrameGraph fg(FrameGraphConfig{W, H});
    auto import = [&](const gpu::Image& img, const char* name) {
        const gpu::ImageDesc& d = img.desc();
        return fg.importTexture(
            name, {.width = d.width, .height = d.height, .format = d.format},
            {img.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, d.usage});
    };
    reflections::UpsampleInputs in;
    in.depth = import(depth, "test.depth");
    in.normal = import(normal, "test.normal");
    in.guide = import(guide, "test.guide");
    TextureHandle lowAHandle = import(lowA, "test.low_a"), lowBHandle = import(lowB, "test.low_b");
    // World = (ndc x, ndc y, depth): the plane term compares depths directly, seen from z = -2.
    in.invViewProj = glm::mat4(1.0f);
    in.eye = glm::vec3(0, 0, -2);
    in.low = lowAHandle;
    std::array<TextureHandle, 2> full;
    full[0] = upsampler.addPass(fg, in, "reflections.upsample", "test.full.0");
    in.low = lowBHandle;
    full[1] = upsampler.addPass(fg, in, "reflections.upsample_method", "test.full.1");
    struct Data {
        TextureHandle a, b;
    };
    fg.addPass<Data>(
        "test.readback", PassType::Transfer,
        [&](PassBuilder& b, Data& d) {
            d.a = b.read(full[0], TextureUsage::TransferSrc);
            d.b = b.read(full[1], TextureUsage::TransferSrc);
            b.sideEffect();
        },
        [&](const Data& d, PassContext& pc) {
            VkBufferImageCopy c{};
            c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            c.imageExtent = {W, H, 1};
            vkCmdCopyImageToBuffer(pc.cmd(), pc.image(d.a), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.get(), 1,
                                   &c);
            c.bufferOffset = VkDeviceSize(W) * H * 8;
            vkCmdCopyImageToBuffer(pc.cmd(), pc.image(d.b), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.get(), 1,
                                   &c);
        });
    gpu::VulkanResourceAllocator allocator(ctx.physicalDevice(), ctx.device());
    gpu::VulkanFrameGraphExecutor executor(ctx.instance(), ctx.physicalDevice(), ctx.device(), ctx.timestampPeriodNs());
    fg.compile(allocator);
    ctx.submitAndWait([&](VkCommandBuffer cmd) { fg.execute(executor, cmd); });
    const auto* data = static_cast<const std::byte*>(readback.mapped());
    return {gpu::decodeRGBA(VK_FORMAT_R16G16B16A16_SFLOAT, data, W * H),
            gpu::decodeRGBA(VK_FORMAT_R16G16B16A16_SFLOAT, data + size_t(W) * H * 8, W * H)};
}

glm::vec4 at(const std::vector<float>& img, uint32_t x, uint32_t y) {
    const float* p = &img[(size_t(y) * W + x) * 4];
    return {p[0], p[1], p[2], p[3]};
}

Images edgeImages(uint32_t edgeX, std::function<bool(uint32_t, uint32_t)> near) {
    Images im;
    im.depth.resize(W * H);
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) im.depth[y * W + x] = near(x, y) ? 0.9f : 0.3f;
    (void)edgeX;
    im.guide = makeGuide(im.depth);
    for (const glm::vec4& g : im.guide) {
        bool n = g.z > 0.5f;
        im.lowA.push_back(n ? glm::vec4(1, 0, 0, 1) : glm::vec4(0, 1, 0, 0.5f));
        im.lowB.push_back(n ? glm::vec4(0, 0, 4, 2) : glm::vec4(3, 0, 0, 0.25f));
    }
    return im;
}

}  // namespace

class UpsampleGpu : public render::test::SharedContextTest<UpsampleGpu> {};

// Two depths, two colours: every full pixel gets exactly its own side's colour, at vertical,
// horizontal and diagonal edges that cut through 2x2 blocks (odd positions).
TEST_F(UpsampleGpu, NeverMixesAcrossADepthEdge) {
    std::vector<std::pair<const char*, std::function<bool(uint32_t, uint32_t)>>> edges = {
        {"vertical at x = 37", [](uint32_t x, uint32_t) { return x < 37; }},
        {"horizontal at y = 13", [](uint32_t, uint32_t y) { return y < 13; }},
        {"diagonal", [](uint32_t x, uint32_t y) { return x + 2 * y < 61; }},
        {"a 3-pixel-wide bar", [](uint32_t x, uint32_t) { return x >= 21 && x < 24; }}};
    for (auto& [name, near] : edges) {
        auto out = upsample(*ctx_, edgeImages(0, near));
        int mixed = 0;
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x) {
                bool n = near(x, y);
                glm::vec4 a = at(out[0], x, y), b = at(out[1], x, y);
                glm::vec4 wantA = n ? glm::vec4(1, 0, 0, 1) : glm::vec4(0, 1, 0, 0.5f);
                glm::vec4 wantB = n ? glm::vec4(0, 0, 4, 2) : glm::vec4(3, 0, 0, 0.25f);
                if (glm::any(glm::greaterThan(glm::abs(a - wantA), glm::vec4(1e-3f))) ||
                    glm::any(glm::greaterThan(glm::abs(b - wantB), glm::vec4(4e-3f)))) {
                    if (++mixed <= 5)
                        ADD_FAILURE() << name << ": pixel " << x << "," << y << " (" << (n ? "near" : "far") << ") got "
                                      << a.r << "," << a.g << "," << a.b << "," << a.a;
                }
            }
        EXPECT_EQ(mixed, 0) << name;
    }
    EXPECT_EQ(gpu::Context::validationMessageCount(), 0);
}

TEST_F(UpsampleGpu, ConstantImageStaysConstant) {
    Images im;
    // A slanted plane (depth changes along x: not an edge) with a constant colour.
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) im.depth.push_back(0.4f + 0.002f * float(x));
    im.guide = makeGuide(im.depth);
    im.lowA.assign(LW * LH, glm::vec4(0.25f, 0.5f, 2.0f, 1.0f));
    im.lowB.assign(LW * LH, glm::vec4(7.0f, 0.0f, 0.125f, 0.5f));
    auto out = upsample(*ctx_, im);
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            ASSERT_NEAR(at(out[0], x, y).b, 2.0f, 2e-3f) << x << "," << y;
            ASSERT_NEAR(at(out[0], x, y).g, 0.5f, 1e-3f) << x << "," << y;
            ASSERT_NEAR(at(out[1], x, y).r, 7.0f, 8e-3f) << x << "," << y;
            ASSERT_NEAR(at(out[1], x, y).a, 0.5f, 1e-3f) << x << "," << y;
        }
    EXPECT_EQ(gpu::Context::validationMessageCount(), 0);
}

// The full pixel its 2x2 traced (the guide's index) keeps that sample's value exactly, where a
// blend of the four neighbours would blur a curved mirror's reflection (MEASUREMENTS.md, issue
// 23: half resolution's mirror band +0.11 dB on the presets suite). Every other pixel stays a
// convex blend, within its four samples' range.
TEST_F(UpsampleGpu, TracedPixelKeepsItsValue) {
    Images im;
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) im.depth.push_back(0.4f + 0.002f * float(x) + 0.001f * float((x * 7 + y * 3) % 5));
    im.guide = makeGuide(im.depth);
    for (uint32_t i = 0; i < LW * LH; ++i) {
        float v = float((i * 37u) % 11u) * 0.25f;  // neighbours differ by up to 2.5
        im.lowA.emplace_back(v, 2.5f - v, 1.0f, 1.0f);
        im.lowB.emplace_back(1.0f, v, 0.0f, 0.5f);
    }
    auto out = upsample(*ctx_, im);
    int exact = 0;
    for (uint32_t y = 0; y < LH; ++y)
        for (uint32_t x = 0; x < LW; ++x) {
            uint32_t index = (uint32_t(im.guide[y * LW + x].w) - 1u) & 3u;
            uint32_t px = 2 * x + (index & 1), py = 2 * y + (index >> 1);
            glm::vec4 want = im.lowA[y * LW + x], got = at(out[0], px, py);
            EXPECT_NEAR(got.r, want.r, 2e-3f) << "traced pixel " << px << "," << py;
            EXPECT_NEAR(got.g, want.g, 2e-3f) << "traced pixel " << px << "," << py;
            EXPECT_NEAR(at(out[1], px, py).g, want.r, 2e-3f) << "traced pixel " << px << "," << py;
            exact += std::abs(got.r - want.r) <= 2e-3f;
        }
    EXPECT_EQ(exact, int(LW * LH));
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            float r = at(out[0], x, y).r;
            EXPECT_GE(r, -1e-3f) << x << "," << y;
            EXPECT_LE(r, 2.5f + 2e-3f) << x << "," << y;
        }
    EXPECT_EQ(gpu::Context::validationMessageCount(), 0);
}
