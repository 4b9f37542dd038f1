// DescriptorWriter writes by the shader's variable names (engine/gpu/pipeline.cpp): the names
// reach the bindings the GLSL declares, and every mistake a binding list used to allow (an
// unknown name, the wrong kind, a binding left out, one written twice) is a std::logic_error
// naming the pipeline, its shader and the binding.
#include "speculum/gpu/context.hpp"
#include "speculum/gpu/pipeline.hpp"
#include "speculum/gpu/resources.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>

using namespace speculum;

namespace {

// The message of the std::logic_error that push() throws, or "" when it throws none.
std::string pushError(const gpu::Context& ctx, const gpu::Pipeline& p, gpu::DescriptorWriter& w) {
    std::string what;
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        try {
            w.push(ctx, cmd, p);
        } catch (const std::logic_error& e) {
            what = e.what();
        }
    });
    return what;
}

void expectMentions(const std::string& what, std::initializer_list<const char*> words) {
    EXPECT_FALSE(what.empty()) << "expected std::logic_error";
    for (const char* w : words) EXPECT_NE(what.find(w), std::string::npos) << "'" << w << "' missing in: " << what;
}

struct UboRig {
    gpu::Context ctx;
    // tests/branch_on_ubo.comp: `params` (uniform block, binding 0) and `outBuf` (storage, 1).
    gpu::Pipeline pipeline = gpu::createComputePipeline(ctx, "tests/branch_on_ubo.comp", 0, "test.writer");
    gpu::Buffer params{ctx, 16, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true, "test.params"};
    gpu::Buffer out{ctx, 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "test.out"};
};

}  // namespace

// The names reach the right bindings: p.x = 0 skips the branch, so the shader writes p.y.
TEST(DescriptorWriter, WritesByNameReachTheShadersBindings) {
    UboRig r;
    EXPECT_EQ(r.pipeline.shader(), "tests/branch_on_ubo.comp");
    ASSERT_EQ(r.pipeline.bindings().size(), 2u);
    const uint32_t p[4] = {0u, 7u, 0u, 0u};
    std::memcpy(r.params.mapped(), p, sizeof(p));
    std::memset(r.out.mapped(), 0, 64);
    r.ctx.submitAndWait([&](VkCommandBuffer cmd) {
        r.pipeline.bind(cmd);
        // Out of binding order on purpose: the writer resolves names, not positions.
        gpu::DescriptorWriter w;
        w.buffer("outBuf", r.out.get()).buffer("params", r.params.get());
        w.push(r.ctx, cmd, r.pipeline);
        vkCmdDispatch(cmd, 1, 1, 1);
    });
    float v = 0.0f;
    std::memcpy(&v, r.out.mapped(), sizeof(v));
    EXPECT_EQ(v, 7.0f);
    EXPECT_EQ(gpu::Context::validationMessageCount(), 0);
}

// The buffers a case writes, by name, in order, and the words its error must hold.
void expectPushError(std::initializer_list<const char*> writes, std::initializer_list<const char*> mentions) {
    UboRig r;
    gpu::DescriptorWriter w;
    for (const char* name : writes) w.buffer(name, std::string(name) == "outBuf" ? r.out.get() : r.params.get());
    expectMentions(pushError(r.ctx, r.pipeline, w), mentions);
}

TEST(DescriptorWriter, UnknownNameThrows) {
    expectPushError({"params", "outBuf", "paramz"}, {"test.writer", "tests/branch_on_ubo.comp", "paramz"});
}

TEST(DescriptorWriter, MissingBindingThrows) {
    expectPushError({"params"}, {"test.writer", "tests/branch_on_ubo.comp", "outBuf", "binding 1"});
}

TEST(DescriptorWriter, NameWrittenTwiceThrows) {
    expectPushError({"params", "outBuf", "params"}, {"test.writer", "params", "twice"});
}

// tests/reflect_kinds.comp: `target` is an image2D, `params` a uniform block.
TEST(DescriptorWriter, WrongKindThrows) {
    gpu::Context ctx;
    gpu::Pipeline p = gpu::createComputePipeline(ctx, "tests/reflect_kinds.comp", 0, "test.kinds");
    {
        gpu::DescriptorWriter w;
        w.sampled("target", VK_NULL_HANDLE, VK_NULL_HANDLE);
        expectMentions(pushError(ctx, p, w),
                       {"test.kinds", "tests/reflect_kinds.comp", "target", "storage image", "sampled()"});
    }
    {
        gpu::DescriptorWriter w;
        w.storage("params", VK_NULL_HANDLE);
        expectMentions(pushError(ctx, p, w), {"test.kinds", "params", "uniform buffer", "storage()"});
    }
    {
        gpu::DescriptorWriter w;
        w.buffer("unusedCube", VK_NULL_HANDLE);
        expectMentions(pushError(ctx, p, w), {"unusedCube", "sampled image", "buffer()"});
    }
}
