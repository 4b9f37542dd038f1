// Frame graph unit tests (no GPU): culling, ordering, barriers, aliasing, errors, dumps.
#include <speculum/framegraph.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

namespace speculum {
namespace {

VkDeviceSize bytesPerPixel(VkFormat format) {
    switch (format) {
    case VK_FORMAT_R8_UNORM: return 1;
    case VK_FORMAT_R16G16B16A16_SFLOAT: return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT: return 16;
    default: return 4;
    }
}

// Size = sum over the mip chain of w*h*bpp*layers, aligned to 256, like a linear allocator.
class FakeAllocator : public ResourceAllocator {
public:
    MemoryRequirements requirements(const TextureInfo& t) const override {
        VkDeviceSize size = 0;
        for (uint32_t m = 0; m < t.desc.mips; ++m) {
            VkDeviceSize w = std::max(1u, t.desc.width >> m);
            VkDeviceSize h = std::max(1u, t.desc.height >> m);
            size += w * h * bytesPerPixel(t.desc.format) * t.desc.layers;
        }
        return {align(size), 256, ~0u};
    }
    MemoryRequirements requirements(const BufferDesc& b, VkBufferUsageFlags) const override {
        return {align(b.size), 256, ~0u};
    }
    static VkDeviceSize align(VkDeviceSize v) { return (v + 255) / 256 * 256; }
};

struct NoData {};

// Declares a pass whose setup only needs the builder; handles live in the test's locals.
void addPass(FrameGraph& fg, const std::string& name, PassType type,
                    const std::function<void(PassBuilder&)>& setup) {
    fg.addPass<NoData>(
        name, type, [&](PassBuilder& b, NoData&) { setup(b); },
        [](const NoData&, PassContext&) {});
}

// The FrameGraphError message thrown by f, or "" when it throws none.
template <class F>
std::string errorOf(F&& f) {
    try {
        f();
    } catch (const FrameGraphError& e) {
        return e.what();
    }
    return "";
}


constexpr VkPipelineStageFlags2 kNone = VK_PIPELINE_STAGE_2_NONE;
constexpr VkPipelineStageFlags2 kCompute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkPipelineStageFlags2 kColorOut = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
constexpr VkPipelineStageFlags2 kDepthTests =
    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
constexpr VkPipelineStageFlags2 kRasterShaders =
    VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
constexpr VkAccessFlags2 kColorRW =
    VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
constexpr VkAccessFlags2 kDepthRW = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;

std::vector<uint32_t> executedPasses(const CompiledGraph& c) {
    std::vector<uint32_t> out;
    for (const CompiledPass& p : c.passes) out.push_back(p.pass);
    return out;
}

const Placement* placementOf(const CompiledGraph& c, uint32_t texture) {
    for (const Placement& p : c.placements) {
        if (p.isTexture && p.resource == texture) return &p;
    }
    return nullptr;
}

}  // namespace

// ---- culling ---------------------------------------------------------------------------------

TEST(FrameGraphCull, UnusedPassIsCulledAndOutputProducerKept) {
    FrameGraph fg({64, 64});
    TextureHandle used, unused;
    addPass(fg, "a.used", PassType::Compute, [&](PassBuilder& b) {
        used = b.write(b.create("a.out", TextureDesc{}), TextureUsage::StorageWrite);
    });
    addPass(fg, "b.unused", PassType::Compute, [&](PassBuilder& b) {
        unused = b.write(b.create("b.out", TextureDesc{}), TextureUsage::StorageWrite);
    });
    fg.markOutput(used);
    FakeAllocator alloc;
    const CompiledGraph& c = fg.compile(alloc);
    EXPECT_EQ(c.passCulled, (std::vector<bool>{false, true}));
    EXPECT_EQ(executedPasses(c), (std::vector<uint32_t>{0}));
    // The culled pass's texture gets no memory.
    EXPECT_EQ(c.placements.size(), 1u);
    EXPECT_EQ(c.placements[0].resource, used.id);
}

TEST(FrameGraphCull, SideEffectPassIsKept) {
    FrameGraph fg({64, 64});
    addPass(fg, "readback.copy", PassType::Compute, [&](PassBuilder& b) {
        b.write(b.create("readback.tmp", TextureDesc{}), TextureUsage::StorageWrite);
        b.sideEffect();
    });
    addPass(fg, "nobody.cares", PassType::Compute, [&](PassBuilder& b) {
        b.write(b.create("nobody.tmp", TextureDesc{}), TextureUsage::StorageWrite);
    });
    FakeAllocator alloc;
    EXPECT_EQ(fg.compile(alloc).passCulled, (std::vector<bool>{false, true}));
}

TEST(FrameGraphCull, ProducersOfOutputChainKeptOthersCulled) {
    FrameGraph fg({64, 64});
    TextureHandle a, b2, c;
    addPass(fg, "p.a", PassType::Compute, [&](PassBuilder& b) {
        a = b.write(b.create("t.a", TextureDesc{}), TextureUsage::StorageWrite);
    });
    addPass(fg, "p.side", PassType::Compute, [&](PassBuilder& b) {
        b.read(a, TextureUsage::Sampled);
        b.write(b.create("t.side", TextureDesc{}), TextureUsage::StorageWrite);
    });
    addPass(fg, "p.b", PassType::Compute, [&](PassBuilder& b) {
        b.read(a, TextureUsage::Sampled);
        b2 = b.write(b.create("t.b", TextureDesc{}), TextureUsage::StorageWrite);
    });
    addPass(fg, "p.c", PassType::Compute, [&](PassBuilder& b) {
        b.read(b2, TextureUsage::Sampled);
        c = b.write(b.create("t.c", TextureDesc{}), TextureUsage::StorageWrite);
    });
    fg.markOutput(c);
    FakeAllocator alloc;
    const CompiledGraph& compiled = fg.compile(alloc);
    EXPECT_EQ(compiled.passCulled, (std::vector<bool>{false, true, false, false}));
    EXPECT_EQ(executedPasses(compiled), (std::vector<uint32_t>{0, 2, 3}));
}

TEST(FrameGraphCull, WriteToImportedResourceIsAnOutput) {
    FrameGraph fg({64, 64});
    TextureHandle history = fg.importTexture("taa.history", {}, {});
    addPass(fg, "taa.resolve", PassType::Compute,
            [&](PassBuilder& b) { b.write(history, TextureUsage::StorageWrite); });
    FakeAllocator alloc;
    const CompiledGraph& c = fg.compile(alloc);
    EXPECT_EQ(c.passCulled, (std::vector<bool>{false}));
    EXPECT_TRUE(c.placements.empty());  // imports are not placed in the transient heap
}

// ---- ordering --------------------------------------------------------------------------------

TEST(FrameGraphOrder, DeclarationOrderIsKeptWhenValid) {
    FrameGraph fg({64, 64});
    TextureHandle x, y;
    addPass(fg, "o.first", PassType::Compute, [&](PassBuilder& b) {
        x = b.write(b.create("x", TextureDesc{}), TextureUsage::StorageWrite);
    });
    addPass(fg, "o.second", PassType::Compute, [&](PassBuilder& b) {
        b.read(x, TextureUsage::Sampled);
        y = b.write(b.create("y", TextureDesc{}), TextureUsage::StorageWrite);
    });
    addPass(fg, "o.third", PassType::Compute, [&](PassBuilder& b) {
        b.read(y, TextureUsage::Sampled);
        b.read(x, TextureUsage::Sampled);
        b.sideEffect();
    });
    FakeAllocator alloc;
    EXPECT_EQ(executedPasses(fg.compile(alloc)), (std::vector<uint32_t>{0, 1, 2}));
}

TEST(FrameGraphOrder, ReadOfLaterVersionMovesItsProducerFirst) {
    FrameGraph fg({64, 64});
    TextureHandle x, out;
    addPass(fg, "o.init", PassType::Compute, [&](PassBuilder& b) {
        x = b.write(b.create("x", TextureDesc{}), TextureUsage::StorageWrite);
    });
    addPass(fg, "o.consumer", PassType::Compute, [&](PassBuilder& b) {
        b.read(TextureHandle{x.id, x.version + 1}, TextureUsage::Sampled);
        out = b.write(b.create("out", TextureDesc{}), TextureUsage::StorageWrite);
    });
    addPass(fg, "o.producer", PassType::Compute,
            [&](PassBuilder& b) { b.write(x, TextureUsage::StorageWrite); });
    fg.markOutput(out);
    FakeAllocator alloc;
    EXPECT_EQ(executedPasses(fg.compile(alloc)), (std::vector<uint32_t>{0, 2, 1}));
}

// ---- barriers --------------------------------------------------------------------------------

// render.gbuffer writes depth and mip 0 of a 4-mip Hi-Z texture; hiz.mip1..3 each sample mip
// N-1 and store mip N of that same texture; light.ssr loads the whole pyramid.
TEST(FrameGraphBarriers, HiZPyramidExactBarriersAndLayouts) {
    FrameGraph fg({64, 64});
    TextureHandle depth, hiz, out;
    addPass(fg, "render.gbuffer", PassType::Raster, [&](PassBuilder& b) {
        depth = b.write(b.create("render.depth", {.format = VK_FORMAT_D32_SFLOAT}),
                        TextureUsage::DepthAttachment);
        hiz = b.write(b.create("hiz.depth", {.format = VK_FORMAT_R32_SFLOAT, .mips = 4}),
                      TextureUsage::ColorAttachment, mipLevel(0));
    });
    for (uint32_t mip = 1; mip <= 3; ++mip) {
        addPass(fg, "hiz.mip" + std::to_string(mip), PassType::Compute, [&](PassBuilder& b) {
            b.read(hiz, TextureUsage::Sampled, mipLevel(mip - 1));
            hiz = b.write(hiz, TextureUsage::StorageWrite, mipLevel(mip));
        });
    }
    addPass(fg, "light.ssr", PassType::Compute, [&](PassBuilder& b) {
        b.read(hiz, TextureUsage::StorageRead);
        out = b.write(b.create("light.ssr", {.format = VK_FORMAT_R16G16B16A16_SFLOAT}),
                      TextureUsage::StorageWrite);
    });
    fg.markOutput(out);
    FakeAllocator alloc;
    const CompiledGraph& c = fg.compile(alloc);
    ASSERT_EQ(executedPasses(c), (std::vector<uint32_t>{0, 1, 2, 3, 4}));
    ASSERT_EQ(depth.id, 0u);
    ASSERT_EQ(hiz.id, 1u);
    ASSERT_EQ(out.id, 2u);

    const VkAccessFlags2 kSampled = VK_ACCESS_2_SHADER_SAMPLED_READ_BIT;
    const VkAccessFlags2 kStoreW = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
    const VkAccessFlags2 kStoreR = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
    const VkImageLayout kUndef = VK_IMAGE_LAYOUT_UNDEFINED;
    const VkImageLayout kGeneral = VK_IMAGE_LAYOUT_GENERAL;
    const VkImageLayout kRead = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    using TB = TextureBarrier;
    // First uses start UNDEFINED with nothing to wait on.
    EXPECT_EQ(c.passes[0].textureBarriers,
              (std::vector<TB>{
                  {0, {0, 1, 0, 1}, kNone, 0, kDepthTests, kDepthRW, kUndef,
                   VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL},
                  {1, {0, 1, 0, 1}, kNone, 0, kColorOut, kColorRW, kUndef,
                   VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL},
              }));
    // hiz.mip1: mip 0 from attachment to sampled; mip 1 fresh for storage.
    EXPECT_EQ(c.passes[1].textureBarriers,
              (std::vector<TB>{
                  {1, {0, 1, 0, 1}, kColorOut, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, kCompute,
                   kSampled, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, kRead},
                  {1, {1, 1, 0, 1}, kNone, 0, kCompute, kStoreW, kUndef, kGeneral},
              }));
    for (uint32_t mip = 2; mip <= 3; ++mip) {
        SCOPED_TRACE("hiz.mip" + std::to_string(mip));
        EXPECT_EQ(c.passes[mip].textureBarriers,
                  (std::vector<TB>{
                      {1, {mip - 1, 1, 0, 1}, kCompute, kStoreW, kCompute, kSampled, kGeneral,
                       kRead},
                      {1, {mip, 1, 0, 1}, kNone, 0, kCompute, kStoreW, kUndef, kGeneral},
                  }));
    }
    // light.ssr: mips 0-2 make the same transition and merge into one range; mip 3 stays in
    // GENERAL but needs the store made visible. light.ssr's output shares memory with the dead
    // depth buffer, so its first barrier waits on depth's last writes.
    EXPECT_EQ(c.passes[4].textureBarriers,
              (std::vector<TB>{
                  {1, {0, 3, 0, 1}, kCompute, 0, kCompute, kStoreR, kRead, kGeneral},
                  {1, {3, 1, 0, 1}, kCompute, kStoreW, kCompute, kStoreR, kGeneral, kGeneral},
                  {2, {0, 1, 0, 1}, kDepthTests, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                   kCompute, kStoreW, kUndef, kGeneral},
              }));
    ASSERT_NE(placementOf(c, depth.id), nullptr);
    ASSERT_NE(placementOf(c, out.id), nullptr);
    EXPECT_EQ(placementOf(c, depth.id)->offset, placementOf(c, out.id)->offset);
    EXPECT_TRUE(c.finalTextureBarriers.empty());
    for (const CompiledPass& p : c.passes) EXPECT_TRUE(p.bufferBarriers.empty());
}

TEST(FrameGraphBarriers, ImportedSwapchainStartsInInitialLayoutAndEndsInFinal) {
    FrameGraph fg({32, 32});
    TextureHandle swap = fg.importTexture(
        "present.swapchain", {.format = VK_FORMAT_B8G8R8A8_UNORM},
        {VK_NULL_HANDLE, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT});
    addPass(fg, "post.tonemap", PassType::Raster,
            [&](PassBuilder& b) { b.write(swap, TextureUsage::ColorAttachment); });
    FakeAllocator alloc;
    const CompiledGraph& c = fg.compile(alloc);
    ASSERT_EQ(c.passes.size(), 1u);
    EXPECT_EQ(c.passes[0].textureBarriers,
              (std::vector<TextureBarrier>{{0, {0, 1, 0, 1}, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                                            0, kColorOut, kColorRW, VK_IMAGE_LAYOUT_UNDEFINED,
                                            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL}}));
    EXPECT_EQ(c.finalTextureBarriers,
              (std::vector<TextureBarrier>{{0, {0, 1, 0, 1}, kColorOut,
                                            VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, kNone, 0,
                                            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                                            VK_IMAGE_LAYOUT_PRESENT_SRC_KHR}}));
}

TEST(FrameGraphBarriers, ImportedWithContentsWaitsOnEarlierWritesEvenInSameLayout) {
    FrameGraph fg({32, 32});
    TextureHandle probe = fg.importTexture(
        "probe.cube", {.width = 16, .height = 16, .layers = 6, .cube = true},
        {VK_NULL_HANDLE, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_UNDEFINED,
         VK_IMAGE_USAGE_SAMPLED_BIT});
    addPass(fg, "light.probe", PassType::Raster, [&](PassBuilder& b) {
        b.read(probe, TextureUsage::Sampled);
        b.sideEffect();
    });
    FakeAllocator alloc;
    const CompiledGraph& c = fg.compile(alloc);
    // All six faces merge into one layer range.
    EXPECT_EQ(c.passes[0].textureBarriers,
              (std::vector<TextureBarrier>{{0, {0, 1, 0, 6}, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                                            VK_ACCESS_2_MEMORY_WRITE_BIT, kRasterShaders,
                                            VK_ACCESS_2_SHADER_SAMPLED_READ_BIT,
                                            VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                            VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}}));
    EXPECT_TRUE(c.finalTextureBarriers.empty());  // finalLayout UNDEFINED: left as is
}

TEST(FrameGraphBarriers, ReadAfterReadInSameLayoutNeedsNoBarrier) {
    FrameGraph fg({32, 32});
    TextureHandle t;
    addPass(fg, "r.write", PassType::Compute, [&](PassBuilder& b) {
        t = b.write(b.create("r.tex", TextureDesc{}), TextureUsage::StorageWrite);
    });
    for (const char* name : {"r.read1", "r.read2"}) {
        addPass(fg, name, PassType::Compute, [&](PassBuilder& b) {
            b.read(t, TextureUsage::Sampled);
            b.sideEffect();
        });
    }
    FakeAllocator alloc;
    const CompiledGraph& c = fg.compile(alloc);
    ASSERT_EQ(c.passes.size(), 3u);
    EXPECT_EQ(c.passes[1].textureBarriers.size(), 1u);
    EXPECT_TRUE(c.passes[2].textureBarriers.empty());
}

TEST(FrameGraphBarriers, BufferWriteThenReadThenWrite) {
    FrameGraph fg({32, 32});
    BufferHandle buf;
    addPass(fg, "cull.write", PassType::Compute, [&](PassBuilder& b) {
        buf = b.write(b.create("cull.args", BufferDesc{1024}), BufferUsage::StorageWrite);
    });
    addPass(fg, "draw.indirect", PassType::Raster, [&](PassBuilder& b) {
        b.read(buf, BufferUsage::Indirect);
        b.sideEffect();  // draws into something outside this small graph
    });
    addPass(fg, "cull.rewrite", PassType::Compute, [&](PassBuilder& b) {
        buf = b.write(buf, BufferUsage::StorageWrite);
    });
    fg.markOutput(buf);
    FakeAllocator alloc;
    const CompiledGraph& c = fg.compile(alloc);
    ASSERT_EQ(executedPasses(c), (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_TRUE(c.passes[0].bufferBarriers.empty());
    EXPECT_EQ(c.passes[1].bufferBarriers,
              (std::vector<BufferBarrier>{{0, kCompute, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                                           VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                                           VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT}}));
    // Write after read: an execution dependency on the reader only.
    EXPECT_EQ(c.passes[2].bufferBarriers,
              (std::vector<BufferBarrier>{{0, VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, 0, kCompute,
                                           VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT}}));
    EXPECT_EQ(fg.bufferUsage(0),
              VkBufferUsageFlags(VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                 VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT));
}

TEST(FrameGraphBarriers, AccessOfDocumentedChoices) {
    AccessInfo sampled = accessOf(TextureUsage::Sampled, PassType::Raster);
    EXPECT_EQ(sampled.stage, kRasterShaders);
    EXPECT_EQ(sampled.layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_FALSE(sampled.writes);
    EXPECT_EQ(accessOf(TextureUsage::Sampled, PassType::Compute).stage, kCompute);
    AccessInfo depthRead = accessOf(TextureUsage::DepthRead, PassType::Raster);
    EXPECT_EQ(depthRead.stage, kDepthTests);
    EXPECT_EQ(depthRead.layout, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);
    AccessInfo present = accessOf(TextureUsage::Present, PassType::Raster);
    EXPECT_EQ(present.stage, kNone);
    EXPECT_EQ(present.access, 0u);
    EXPECT_EQ(present.layout, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
    AccessInfo dst = accessOf(TextureUsage::TransferDst, PassType::Transfer);
    EXPECT_EQ(dst.stage, VK_PIPELINE_STAGE_2_TRANSFER_BIT);
    EXPECT_EQ(dst.layout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    EXPECT_TRUE(dst.writes);
}

// ---- sizes, usage, lifetimes ------------------------------------------------------------------

TEST(FrameGraphResolve, RelativeSizesAndUsageUnion) {
    FrameGraph fg({1279, 721});
    TextureHandle half, tiny;
    addPass(fg, "s.write", PassType::Raster, [&](PassBuilder& b) {
        half = b.write(b.create("s.half", {.relativeScale = 0.5f}), TextureUsage::ColorAttachment);
    });
    addPass(fg, "s.tiny", PassType::Compute, [&](PassBuilder& b) {
        b.read(half, TextureUsage::Sampled);
        tiny = b.write(b.create("s.tiny", {.relativeScale = 0.0001f}),
                       TextureUsage::StorageWrite);
    });
    fg.markOutput(tiny);
    FakeAllocator alloc;
    const CompiledGraph& c = fg.compile(alloc);
    EXPECT_EQ(fg.texture(half.id).desc.width, 640u);   // ceil(639.5)
    EXPECT_EQ(fg.texture(half.id).desc.height, 361u);  // ceil(360.5)
    EXPECT_EQ(fg.texture(tiny.id).desc.width, 1u);
    EXPECT_EQ(fg.texture(tiny.id).desc.height, 1u);
    EXPECT_EQ(fg.texture(half.id).usage,
              VkImageUsageFlags(VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT));
    EXPECT_EQ(c.textureLifetimes[half.id].first, 0u);
    EXPECT_EQ(c.textureLifetimes[half.id].last, 1u);
    EXPECT_EQ(c.textureLifetimes[tiny.id].first, 1u);
    EXPECT_EQ(c.textureLifetimes[tiny.id].last, 1u);
}

// ---- aliasing --------------------------------------------------------------------------------

// a (pass 0-1) and b (pass 2-3) never live together; c lives through passes 1-2 and overlaps
// both.
static void declareAliasGraph(FrameGraph& fg, TextureHandle& a, TextureHandle& b,
                              TextureHandle& c) {
    addPass(fg, "al.0", PassType::Compute, [&](PassBuilder& pb) {
        a = pb.write(pb.create("al.a", TextureDesc{}), TextureUsage::StorageWrite);
    });
    addPass(fg, "al.1", PassType::Compute, [&](PassBuilder& pb) {
        pb.read(a, TextureUsage::Sampled);
        c = pb.write(pb.create("al.c", TextureDesc{}), TextureUsage::StorageWrite);
    });
    addPass(fg, "al.2", PassType::Compute, [&](PassBuilder& pb) {
        pb.read(c, TextureUsage::Sampled);
        b = pb.write(pb.create("al.b", TextureDesc{}), TextureUsage::StorageWrite);
    });
    addPass(fg, "al.3", PassType::Compute, [&](PassBuilder& pb) {
        pb.read(b, TextureUsage::Sampled);
        pb.sideEffect();
    });
}

TEST(FrameGraphAliasing, DisjointLifetimesShareOffsetOverlappingDoNot) {
    FrameGraph fg({64, 64});
    TextureHandle a, b, c;
    declareAliasGraph(fg, a, b, c);
    FakeAllocator alloc;
    const CompiledGraph& compiled = fg.compile(alloc);
    const VkDeviceSize size = 64 * 64 * 4;
    ASSERT_EQ(compiled.placements.size(), 3u);
    EXPECT_EQ(placementOf(compiled, a.id)->offset, placementOf(compiled, b.id)->offset);
    EXPECT_NE(placementOf(compiled, a.id)->offset, placementOf(compiled, c.id)->offset);
    EXPECT_EQ(placementOf(compiled, c.id)->size, size);
    EXPECT_EQ(compiled.memory.transientWithAliasing, 2 * size);
    EXPECT_EQ(compiled.memory.transientWithoutAliasing, 3 * size);
    EXPECT_LT(compiled.memory.transientWithAliasing, compiled.memory.transientWithoutAliasing);
}

TEST(FrameGraphAliasing, DisabledAliasingPlacesEverythingApart) {
    FrameGraph fg({64, 64, false});
    TextureHandle a, b, c;
    declareAliasGraph(fg, a, b, c);
    FakeAllocator alloc;
    const CompiledGraph& compiled = fg.compile(alloc);
    EXPECT_NE(placementOf(compiled, a.id)->offset, placementOf(compiled, b.id)->offset);
    EXPECT_EQ(compiled.memory.transientWithAliasing, compiled.memory.transientWithoutAliasing);
}

TEST(FrameGraphAliasing, PlacementsRespectAlignment) {
    class OddAllocator : public FakeAllocator {
    public:
        MemoryRequirements requirements(const TextureInfo&) const override {
            return {1000, 4096, ~0u};
        }
    };
    FrameGraph fg({64, 64});
    TextureHandle x, y;
    addPass(fg, "al.both", PassType::Compute, [&](PassBuilder& b) {
        x = b.write(b.create("al.x", TextureDesc{}), TextureUsage::StorageWrite);
        y = b.write(b.create("al.y", TextureDesc{}), TextureUsage::StorageWrite);
        b.sideEffect();
    });
    OddAllocator alloc;
    const CompiledGraph& c = fg.compile(alloc);
    EXPECT_EQ(placementOf(c, x.id)->offset, 0u);
    EXPECT_EQ(placementOf(c, y.id)->offset, 4096u);
    EXPECT_EQ(c.memory.transientWithoutAliasing, 2 * 4096u);
}

// ---- user errors -----------------------------------------------------------------------------

TEST(FrameGraphErrors, StaleHandleNamesPassAndResource) {
    FrameGraph fg({64, 64});
    TextureHandle v1;
    addPass(fg, "x.first", PassType::Compute, [&](PassBuilder& b) {
        v1 = b.write(b.create("x.y", TextureDesc{}), TextureUsage::StorageWrite);
    });
    addPass(fg, "x.second", PassType::Compute,
            [&](PassBuilder& b) { b.write(v1, TextureUsage::StorageWrite); });
    std::string err = errorOf([&] {
        addPass(fg, "a.b", PassType::Compute,
                [&](PassBuilder& b) { b.read(v1, TextureUsage::Sampled); });
    });
    EXPECT_EQ(err, "pass 'a.b' uses stale handle of 'x.y' (version 1, current 2)");
}

TEST(FrameGraphErrors, PyramidReadThenWriteOfSameTextureIsNotStale) {
    FrameGraph fg({64, 64});
    TextureHandle h;
    addPass(fg, "p.base", PassType::Compute, [&](PassBuilder& b) {
        h = b.write(b.create("p.pyr", {.mips = 2}), TextureUsage::StorageWrite, mipLevel(0));
    });
    std::string err = errorOf([&] {
        addPass(fg, "p.mip1", PassType::Compute, [&](PassBuilder& b) {
            b.read(h, TextureUsage::Sampled, mipLevel(0));
            h = b.write(h, TextureUsage::StorageWrite, mipLevel(1));
        });
    });
    EXPECT_EQ(err, "");
    EXPECT_EQ(h.version, 2u);
}

TEST(FrameGraphErrors, ReadBeforeWrite) {
    FrameGraph fg({64, 64});
    addPass(fg, "p", PassType::Compute, [&](PassBuilder& b) {
        b.read(b.create("r", TextureDesc{}), TextureUsage::Sampled);
        b.sideEffect();
    });
    FakeAllocator alloc;
    EXPECT_EQ(errorOf([&] { fg.compile(alloc); }), "pass 'p' reads 'r' before any pass writes it");
}

TEST(FrameGraphErrors, Cycle) {
    FrameGraph fg({64, 64});
    TextureHandle x, y;
    addPass(fg, "init", PassType::Compute, [&](PassBuilder& b) {
        x = b.write(b.create("x", TextureDesc{}), TextureUsage::StorageWrite);
        y = b.write(b.create("y", TextureDesc{}), TextureUsage::StorageWrite);
    });
    // 'a' reads the version of x that 'b' produces, and 'b' reads the y that 'a' produces.
    addPass(fg, "a", PassType::Compute, [&](PassBuilder& b) {
        b.read(TextureHandle{x.id, x.version + 1}, TextureUsage::Sampled);
        y = b.write(y, TextureUsage::StorageWrite);
    });
    addPass(fg, "b", PassType::Compute, [&](PassBuilder& b) {
        b.read(y, TextureUsage::Sampled);
        x = b.write(x, TextureUsage::StorageWrite);
        b.sideEffect();
    });
    FakeAllocator alloc;
    EXPECT_EQ(errorOf([&] { fg.compile(alloc); }), "cycle between passes 'a' and 'b'");
}

TEST(FrameGraphErrors, AttachmentSizeMismatch) {
    FrameGraph fg({640, 360});
    addPass(fg, "p", PassType::Raster, [&](PassBuilder& b) {
        b.write(b.create("a", TextureDesc{}), TextureUsage::ColorAttachment);
        b.write(b.create("b", {.relativeScale = 0.5f}), TextureUsage::ColorAttachment);
        b.sideEffect();
    });
    FakeAllocator alloc;
    EXPECT_EQ(errorOf([&] { fg.compile(alloc); }),
              "pass 'p': attachment 'a' is 640x360 but 'b' is 320x180");
}

TEST(FrameGraphErrors, AttachmentMipsOfMatchingExtentAreFine) {
    FrameGraph fg({640, 360});
    addPass(fg, "p", PassType::Raster, [&](PassBuilder& b) {
        b.write(b.create("a", {.mips = 2}), TextureUsage::ColorAttachment, mipLevel(1));
        b.write(b.create("b", {.relativeScale = 0.5f}), TextureUsage::DepthAttachment);
        b.sideEffect();
    });
    FakeAllocator alloc;
    EXPECT_EQ(errorOf([&] { fg.compile(alloc); }), "");
}

TEST(FrameGraphErrors, MisusedUsagesAreRejectedWithNames) {
    FrameGraph fg({64, 64});
    std::string err = errorOf([&] {
        addPass(fg, "c.pass", PassType::Compute, [&](PassBuilder& b) {
            b.write(b.create("c.tex", TextureDesc{}), TextureUsage::ColorAttachment);
        });
    });
    EXPECT_NE(err.find("'c.pass'"), std::string::npos) << err;
    EXPECT_NE(err.find("'c.tex'"), std::string::npos) << err;
    err = errorOf([&] {
        addPass(fg, "c.range", PassType::Compute, [&](PassBuilder& b) {
            b.write(b.create("c.small", {.mips = 2}), TextureUsage::StorageWrite, mipLevel(2));
        });
    });
    EXPECT_NE(err.find("'c.small'"), std::string::npos) << err;
}

// ---- dumps -----------------------------------------------------------------------------------

TEST(FrameGraphDump, JsonAndDotNamePassesResourcesAndCulling) {
    FrameGraph fg({64, 64});
    TextureHandle g;
    addPass(fg, "render.gbuffer", PassType::Raster, [&](PassBuilder& b) {
        g = b.write(b.create("render.albedo", TextureDesc{}), TextureUsage::ColorAttachment);
    });
    addPass(fg, "debug.unused", PassType::Compute, [&](PassBuilder& b) {
        b.read(g, TextureUsage::Sampled);
        b.write(b.create("debug.tmp", TextureDesc{}), TextureUsage::StorageWrite);
    });
    fg.markOutput(g);
    FakeAllocator alloc;
    fg.compile(alloc);
    nlohmann::json j = fg.dumpJson();
    ASSERT_EQ(j["passes"].size(), 2u);
    EXPECT_EQ(j["passes"][0]["name"], "render.gbuffer");
    EXPECT_EQ(j["passes"][0]["culled"], false);
    EXPECT_EQ(j["passes"][0]["order"], 0);
    EXPECT_EQ(j["passes"][0]["textureBarriers"].size(), 1u);
    EXPECT_EQ(j["passes"][1]["name"], "debug.unused");
    EXPECT_EQ(j["passes"][1]["culled"], true);
    EXPECT_EQ(j["textures"][0]["name"], "render.albedo");
    EXPECT_EQ(j["textures"][0]["placement"]["size"], 64 * 64 * 4);
    EXPECT_TRUE(j["textures"][1]["placement"].is_null());
    EXPECT_EQ(j["memory"]["transientWithAliasing"], 64 * 64 * 4);

    std::string dot = fg.dumpDot();
    EXPECT_EQ(dot.rfind("digraph", 0), 0u);
    EXPECT_NE(dot.find("\"render.gbuffer"), std::string::npos);
    EXPECT_NE(dot.find("\"debug.unused\", style=filled, fillcolor=lightgrey"), std::string::npos)
        << dot;
    EXPECT_NE(dot.find("\"render.albedo"), std::string::npos);
    EXPECT_NE(dot.find("p0 -> t0"), std::string::npos);
    EXPECT_NE(dot.find("t0 -> p1"), std::string::npos);
}

}  // namespace speculum
