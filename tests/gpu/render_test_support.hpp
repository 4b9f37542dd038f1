// Shared by the render_* GPU tests: tiny scenes built in code and one-frame rendering with
// readback of the renderer's images.
#pragma once

#include "speculum/framegraph.hpp"
#include "speculum/gpu/context.hpp"
#include "speculum/gpu/fg_executor.hpp"
#include "speculum/gpu/pipeline.hpp"
#include "speculum/gpu/resources.hpp"
#include "speculum/render/renderer.hpp"
#include "speculum/scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace speculum::render::test {

// A test suite sharing one Vulkan context (device creation and validation layers cost about a
// second each): `class MySuite : public SharedContextTest<MySuite> {};`, then ctx_ in the tests.
template <typename Suite>
class SharedContextTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() { ctx_ = new gpu::Context(gpu::ContextOptions{}); }
    static void TearDownTestSuite() {
        delete ctx_;
        ctx_ = nullptr;
    }
    static inline gpu::Context* ctx_ = nullptr;
};

// A suite with a context of its own per test whose teardown fails the test on any validation
// message: `class MySuite : public ValidatedContextTest {};`, then ctx in the tests.
class ValidatedContextTest : public ::testing::Test {
protected:
    void TearDown() override {
        EXPECT_EQ(gpu::Context::validationMessageCount(), 0);
        for (const std::string& m : gpu::Context::validationMessages()) ADD_FAILURE() << m;
    }
    gpu::Context ctx;
};

// The renderer's passes (render_gbuffer_test.cpp, render_lighting_test.cpp): one suite over two
// files, so one fixture class (gtest requires it).
class RenderPasses : public ValidatedContextTest {};

// The pixel a world point lands in (its centre is the nearest pixel centre).
inline glm::ivec2 pixelOf(const CameraState& c, glm::vec3 world) {
    glm::vec4 clip = c.viewProj * glm::vec4(world, 1.0f);
    glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return glm::ivec2(glm::floor((ndc * 0.5f + 0.5f) * glm::vec2(c.width, c.height)));
}

// Runs a test kernel over `queries` (64 to a workgroup, its buffers `Queries` and `Results`):
// `bind` writes the kernel's other descriptors into the writer and pushes its constants.
// Returns `perQuery` vec4 results per query.
template <typename Query>
std::vector<glm::vec4> runQueries(const gpu::Context& ctx, const gpu::Pipeline& pipeline, const std::vector<Query>& queries,
                                  size_t perQuery,
                                  const std::function<void(VkCommandBuffer, gpu::DescriptorWriter&)>& bind) {
    gpu::Buffer in(ctx, sizeof(Query) * queries.size(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "test.queries");
    std::memcpy(in.mapped(), queries.data(), in.size());
    gpu::Buffer out(ctx, sizeof(glm::vec4) * perQuery * queries.size(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true,
                    "test.results");
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        pipeline.bind(cmd);
        gpu::DescriptorWriter w;
        w.buffer("Queries", in.get()).buffer("Results", out.get());
        bind(cmd, w);
        vkCmdDispatch(cmd, (uint32_t(queries.size()) + 63) / 64, 1, 1);
    });
    std::vector<glm::vec4> results(perQuery * queries.size());
    std::memcpy(results.data(), out.mapped(), results.size() * sizeof(glm::vec4));
    return results;
}

// A dielectric material of one grey level and roughness.
inline Material greyMaterial(const std::string& name, float grey, float roughness) {
    Material m;
    m.name = name;
    m.baseColor = glm::vec4(grey, grey, grey, 1.0f);
    m.metallic = 0.0f;
    m.roughness = roughness;
    return m;
}

// A square of side 2 * half in the plane through `center` spanned by axes u and v; its front
// face (counter-clockwise, glTF) looks along cross(u, v).
inline Primitive square(glm::vec3 center, glm::vec3 u, glm::vec3 v, float half, int material) {
    Primitive p;
    glm::vec3 n = glm::normalize(glm::cross(u, v));
    const glm::vec2 corners[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const glm::vec2& c : corners) {
        Vertex vert{};
        vert.position = center + (u * c.x + v * c.y) * half;
        vert.normal = n;
        vert.tangent = glm::vec4(glm::normalize(u), 1.0f);
        vert.uv = c * 0.5f + 0.5f;
        p.vertices.push_back(vert);
    }
    p.indices = {0, 1, 2, 0, 2, 3};
    p.material = material;
    p.boundsMin = glm::min(glm::min(p.vertices[0].position, p.vertices[1].position),
                           glm::min(p.vertices[2].position, p.vertices[3].position));
    p.boundsMax = glm::max(glm::max(p.vertices[0].position, p.vertices[1].position),
                           glm::max(p.vertices[2].position, p.vertices[3].position));
    return p;
}

// Adds a mesh of one primitive with an identity instance and grows the scene bounds.
inline void addMesh(Scene& scene, const Primitive& p) {
    bool first = scene.instances.empty();
    Mesh mesh;
    mesh.primitives.push_back(p);
    scene.meshes.push_back(mesh);
    scene.instances.push_back({-1, int(scene.meshes.size() - 1), glm::mat4(1.0f)});
    scene.boundsMin = first ? p.boundsMin : glm::min(scene.boundsMin, p.boundsMin);
    scene.boundsMax = first ? p.boundsMax : glm::max(scene.boundsMax, p.boundsMax);
}

struct Frame {
    uint32_t width = 0, height = 0;
    std::map<std::string, std::vector<float>> images;  // by resource name, RGBA float
    glm::vec4 at(const std::string& name, uint32_t x, uint32_t y) const {
        const float* p = &images.at(name)[(size_t(y) * width + x) * 4];
        return {p[0], p[1], p[2], p[3]};
    }
};

// Renders one frame (depth prepass, shadow, shadow mask, G-buffer, lighting, tonemap) and
// reads back render.linear, render.color, render.normal, render.emissive and, when the scene
// has a directional light, render.shadow_mask.
inline Frame renderFrame(const gpu::Context& ctx, Renderer& renderer, const CameraState& camera) {
    FrameGraph fg(FrameGraphConfig{camera.width, camera.height});
    FrameInputs inputs{camera, camera};
    GBuffer g = renderer.addGBufferPasses(fg, inputs);
    TextureHandle linear = renderer.addLightingPass(fg, inputs, g);
    TextureHandle color = renderer.addTonemapPass(fg, linear);

    std::vector<TextureHandle> reads = {linear, color, g.normal, g.emissive};
    if (g.shadowMask.valid()) reads.push_back(g.shadowMask);
    std::vector<gpu::Buffer> buffers;
    for (TextureHandle h : reads) {
        (void)h;
        buffers.emplace_back(ctx, VkDeviceSize(camera.width) * camera.height * 8,
                             VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, "test.readback");
    }
    struct Data {
        std::vector<TextureHandle> reads;
    };
    fg.addPass<Data>(
        "test.readback", PassType::Transfer,
        [&](PassBuilder& b, Data& d) {
            for (TextureHandle h : reads) d.reads.push_back(b.read(h, TextureUsage::TransferSrc));
            b.sideEffect();
        },
        [&buffers](const Data& d, PassContext& pc) {
            for (size_t i = 0; i < d.reads.size(); ++i) {
                VkExtent2D e = pc.extent(d.reads[i]);
                VkBufferImageCopy copy{};
                copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                copy.imageExtent = {e.width, e.height, 1};
                vkCmdCopyImageToBuffer(pc.cmd(), pc.image(d.reads[i]),
                                       VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffers[i].get(), 1,
                                       &copy);
            }
        });
    gpu::VulkanResourceAllocator allocator(ctx.physicalDevice(), ctx.device());
    gpu::VulkanFrameGraphExecutor executor(ctx.instance(), ctx.physicalDevice(), ctx.device(),
                                           ctx.timestampPeriodNs());
    fg.compile(allocator);
    ctx.submitAndWait([&](VkCommandBuffer cmd) { fg.execute(executor, cmd); });

    Frame frame{camera.width, camera.height, {}};
    size_t n = size_t(camera.width) * camera.height;
    for (size_t i = 0; i < reads.size(); ++i) {
        const TextureInfo& info = fg.texture(reads[i].id);
        frame.images[info.name] = gpu::decodeRGBA(info.desc.format, buffers[i].mapped(), n);
    }
    return frame;
}

// Vulkan cube face selection (spec, "Cube Map Face Selection"): face and (s, t) in [0, 1].
inline uint32_t cubeFace(glm::dvec3 d, double& s, double& t) {
    glm::dvec3 a = glm::abs(d);
    double sc, tc, ma;
    uint32_t face;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x >= 0 ? 0 : 1;
        ma = a.x;
        sc = d.x >= 0 ? -d.z : d.z;
        tc = -d.y;
    } else if (a.y >= a.z) {
        face = d.y >= 0 ? 2 : 3;
        ma = a.y;
        sc = d.x;
        tc = d.y >= 0 ? d.z : -d.z;
    } else {
        face = d.z >= 0 ? 4 : 5;
        ma = a.z;
        sc = d.z >= 0 ? d.x : -d.x;
        tc = -d.y;
    }
    s = 0.5 * (sc / ma + 1.0);
    t = 0.5 * (tc / ma + 1.0);
    return face;
}

struct Texel {
    uint32_t face;
    int x, y;
};

inline Texel cubeTexel(glm::dvec3 d, uint32_t res) {
    double s, t;
    uint32_t f = cubeFace(d, s, t);
    auto clampi = [res](double v) { return std::clamp(int(std::floor(v * res)), 0, int(res) - 1); };
    return {f, clampi(s), clampi(t)};
}

}  // namespace speculum::render::test
