// The engine seam's frame-graph features (no GPU): history that the graph swaps each frame with a
// validity known after execution, textures sized relative to another texture, and two modules
// composed by typed handles (the second takes the first's outputs, as reflections takes probes').
#include <speculum/framegraph.hpp>

#include <gtest/gtest.h>

#include <algorithm>

namespace speculum {
namespace {

class FakeAllocator : public ResourceAllocator {
public:
    MemoryRequirements requirements(const TextureInfo& t) const override {
        return {VkDeviceSize(t.desc.width) * t.desc.height * 8 * t.desc.layers * t.desc.mips, 256, ~0u};
    }
    MemoryRequirements requirements(const BufferDesc& b, VkBufferUsageFlags) const override { return {b.size, 256, ~0u}; }
};

struct NoData {};

void addPass(FrameGraph& fg, const std::string& name, const std::function<void(PassBuilder&)>& setup) {
    fg.addPass<NoData>(
        name, PassType::Compute, [&](PassBuilder& b, NoData&) { setup(b); }, [](const NoData&, PassContext&) {});
}

VkImage fakeImage(uintptr_t v) {
    return reinterpret_cast<VkImage>(v);
}

const TextureDesc kHistoryDesc{.width = 64, .height = 32, .format = VK_FORMAT_R16G16B16A16_SFLOAT};

// One frame of a module that reads its history and, when `writes`, writes the next one (a frame
// that skips the write: the module stopped early, or its history pass was not added).
HistoryHandles historyFrame(FrameGraph& fg, History& h, bool writes) {
    HistoryHandles handles = fg.importHistory("test.history", h);
    TextureHandle out;
    addPass(fg, "test.reproject", [&](PassBuilder& b) {
        b.read(handles.previous, TextureUsage::Sampled);
        out = b.write(b.create("test.out", {.format = VK_FORMAT_R16G16B16A16_SFLOAT}), TextureUsage::StorageWrite);
    });
    if (writes) {
        addPass(fg, "test.history", [&](PassBuilder& b) {
            b.read(out, TextureUsage::TransferSrc);
            fg.markOutput(b.write(handles.current, TextureUsage::TransferDst));
        });
    } else {
        fg.markOutput(out);
    }
    fg.compile(FakeAllocator{});
    fg.commitHistories();
    return handles;
}

}  // namespace

TEST(FrameGraphHistory, SwapsWhenWrittenAndIsValidOnlyAfterAWrite) {
    History h(kHistoryDesc, fakeImage(0x10), fakeImage(0x20), VK_IMAGE_USAGE_SAMPLED_BIT);
    EXPECT_FALSE(h.valid()) << "nothing was written before the first frame";
    {
        FrameGraph fg({64, 32});
        HistoryHandles first = historyFrame(fg, h, true);
        EXPECT_FALSE(first.valid);
        EXPECT_EQ(fg.importedTexture(first.current.id)->image, fakeImage(0x10));
        EXPECT_EQ(fg.importedTexture(first.previous.id)->image, fakeImage(0x20));
        EXPECT_EQ(fg.texture(first.previous.id).desc.width, 64u);
    }
    EXPECT_TRUE(h.valid());
    EXPECT_EQ(h.previousImage(), fakeImage(0x10)) << "what frame 1 wrote is frame 2's previous";
    {
        FrameGraph fg({64, 32});
        HistoryHandles second = historyFrame(fg, h, true);
        EXPECT_TRUE(second.valid);
        EXPECT_EQ(fg.importedTexture(second.previous.id)->image, fakeImage(0x10));
        EXPECT_EQ(fg.importedTexture(second.current.id)->image, fakeImage(0x20));
    }
    EXPECT_EQ(h.previousImage(), fakeImage(0x20));
    {
        // Nothing writes the current image: no swap, and the next frame must not trust its
        // previous image.
        FrameGraph fg({64, 32});
        historyFrame(fg, h, false);
    }
    EXPECT_FALSE(h.valid());
    EXPECT_EQ(h.previousImage(), fakeImage(0x20));
    {
        FrameGraph fg({64, 32});
        historyFrame(fg, h, true);
    }
    EXPECT_TRUE(h.valid());
    h.invalidate();
    EXPECT_FALSE(h.valid());
}

TEST(FrameGraphHistory, CommitBeforeCompileIsAnError) {
    FrameGraph fg({8, 8});
    EXPECT_THROW(fg.commitHistories(), FrameGraphError);
}

TEST(FrameGraphSizes, TextureSizedRelativeToAnotherTexture) {
    FrameGraph fg({1920, 1080});
    TextureHandle full, half, quarterOfImport, output;
    TextureHandle imported = fg.importTexture("test.import", {.width = 317, .height = 181}, {});
    addPass(fg, "test.sizes", [&](PassBuilder& b) {
        full = b.write(b.create("test.full", {.width = 641, .height = 359}), TextureUsage::StorageWrite);
        half = b.write(b.create("test.half", {.relativeScale = 0.5f, .relativeTo = full}), TextureUsage::StorageWrite);
        quarterOfImport = b.write(b.create("test.quarter", {.relativeScale = 0.25f, .relativeTo = imported}),
                                  TextureUsage::StorageWrite);
        output = b.write(b.create("test.output", {.relativeScale = 0.5f}), TextureUsage::StorageWrite);
        b.sideEffect();
    });
    EXPECT_EQ(fg.texture(half.id).desc.width, 321u);  // ceil(641 / 2)
    EXPECT_EQ(fg.texture(half.id).desc.height, 180u);
    EXPECT_EQ(fg.texture(quarterOfImport.id).desc.width, 80u);  // ceil(317 / 4)
    EXPECT_EQ(fg.texture(quarterOfImport.id).desc.height, 46u);
    EXPECT_EQ(fg.texture(output.id).desc.width, 960u);  // no relativeTo: the output
    EXPECT_EQ(fg.texture(output.id).desc.height, 540u);
}

TEST(FrameGraphSizes, RelativeToAMissingTextureIsAnError) {
    FrameGraph fg({64, 64});
    std::string message;
    try {
        addPass(fg, "test.bad", [&](PassBuilder& b) { b.create("test.orphan", {.relativeTo = TextureHandle{7, 0}}); });
    } catch (const FrameGraphError& e) {
        message = e.what();
    }
    EXPECT_NE(message.find("test.orphan"), std::string::npos) << message;
}

namespace {

// Two modules in the shape of the real ones: each one entry point taking typed handles and
// returning typed handles; the host hands the first's outputs to the second.
struct ProbeLikeOutputs {
    TextureHandle cubes;
    BufferHandle records;
};
ProbeLikeOutputs addProbeLike(FrameGraph& fg) {
    ProbeLikeOutputs out;
    addPass(fg, "probes.capture", [&](PassBuilder& b) {
        out.cubes = b.write(b.create("probes.cubes", {.width = 16, .height = 16, .layers = 6, .cube = true}),
                            TextureUsage::StorageWrite);
        out.records = b.write(b.create("probes.records", BufferDesc{256}), BufferUsage::StorageWrite);
    });
    return out;
}
TextureHandle addReflectionLike(FrameGraph& fg, const ProbeLikeOutputs& probes, TextureHandle lit) {
    TextureHandle out;
    addPass(fg, "reflections.resolve", [&](PassBuilder& b) {
        b.read(probes.cubes, TextureUsage::Sampled);
        b.read(probes.records, BufferUsage::StorageRead);
        b.read(lit, TextureUsage::Sampled);
        out = b.write(b.create("reflections.lit", TextureDesc{}), TextureUsage::StorageWrite);
    });
    return out;
}

}  // namespace

TEST(ModuleSeam, TwoModulesComposedByHandlesRunInOrderAndCullTogether) {
    for (bool used : {true, false}) {
        FrameGraph fg({32, 32});
        TextureHandle lit;
        addPass(fg, "render.lighting", [&](PassBuilder& b) {
            lit = b.write(b.create("render.linear", TextureDesc{}), TextureUsage::StorageWrite);
        });
        // The host composes: the probe module's outputs are the reflection module's inputs.
        ProbeLikeOutputs probes = addProbeLike(fg);
        TextureHandle shown = addReflectionLike(fg, probes, lit);
        addPass(fg, "render.tonemap", [&](PassBuilder& b) {
            TextureHandle color = b.write(b.create("render.color", TextureDesc{}), TextureUsage::StorageWrite);
            b.read(used ? shown : lit, TextureUsage::Sampled);
            fg.markOutput(color);
        });
        const CompiledGraph& c = fg.compile(FakeAllocator{});
        auto position = [&](const std::string& name) {
            for (size_t i = 0; i < c.passes.size(); ++i)
                if (fg.passName(c.passes[i].pass) == name) return int(i);
            return -1;
        };
        if (used) {
            ASSERT_GE(position("probes.capture"), 0);
            EXPECT_LT(position("probes.capture"), position("reflections.resolve"));
            EXPECT_LT(position("reflections.resolve"), position("render.tonemap"));
        } else {
            // Nobody reads the reflection: both modules' passes are culled, the engine's stay.
            EXPECT_EQ(position("probes.capture"), -1);
            EXPECT_EQ(position("reflections.resolve"), -1);
            EXPECT_GE(position("render.tonemap"), 0);
        }
    }
}

}  // namespace speculum
