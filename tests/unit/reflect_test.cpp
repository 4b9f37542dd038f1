// SPIR-V reflection of descriptor bindings (engine/gpu/reflect.cpp) on the project's compiled
// shaders: the table must say what the GLSL says, since pipelines build their layouts from it.
#include "speculum/gpu/reflect.hpp"
#include "speculum/gpu/pipeline.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

using namespace speculum;

namespace {

std::vector<gpu::ReflectedBinding> reflect(const std::string& shader, VkShaderStageFlagBits stage) {
    return gpu::reflectBindings(gpu::loadSpirv(shader), stage, shader);
}

struct Expected {
    const char* name;
    uint32_t binding;
    VkDescriptorType type;
    uint32_t count = 1;
};

void expectBinding(const gpu::ReflectedBinding& b, const Expected& e, VkShaderStageFlags stages) {
    EXPECT_EQ(b.name, e.name);
    EXPECT_EQ(b.binding, e.binding) << e.name;
    EXPECT_EQ(b.type, e.type) << e.name;
    EXPECT_EQ(b.stages, stages) << e.name;
    EXPECT_EQ(b.count, e.count) << e.name;
}

// The table in binding order, every row of it and nothing more, each in `stages`.
void expectBindings(const std::vector<gpu::ReflectedBinding>& table, VkShaderStageFlags stages,
                    std::initializer_list<Expected> expected) {
    ASSERT_EQ(table.size(), expected.size());
    size_t i = 0;
    for (const Expected& e : expected) expectBinding(table[i++], e, stages);
}

constexpr VkDescriptorType kSampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
constexpr VkDescriptorType kStorageImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
constexpr VkDescriptorType kStorageBuffer = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
constexpr VkDescriptorType kUniformBuffer = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
constexpr VkShaderStageFlags kCompute = VK_SHADER_STAGE_COMPUTE_BIT;

}  // namespace

// modules/probes/shaders/debug.comp: two textures, the probe records (an anonymous block: its type
// name), the probe cubes, the output image; bindings 0-4 by way of PROBES_*_BINDING.
TEST(Reflect, ProbesDebugShaderAsTheGlslDeclaresIt) {
    expectBindings(reflect("probes/debug.comp", VK_SHADER_STAGE_COMPUTE_BIT), kCompute,
                   {{"depthTex", 0, kSampled},
                    {"normalTex", 1, kSampled},
                    {"ProbeBuffer", 2, kStorageBuffer},
                    {"probeCubes", 3, kSampled},
                    {"outImage", 4, kStorageImage}});
}

// tests/shaders/reflect_kinds.comp: every kind, an array, a named block (its instance name)
// and a binding main() never reads, which is listed: the table is the declaration.
TEST(Reflect, KindsArraysBlockNamesAndUnusedBindings) {
    expectBindings(reflect("tests/reflect_kinds.comp", VK_SHADER_STAGE_COMPUTE_BIT), kCompute,
                   {{"textures", 0, kSampled, 3},
                    {"target", 1, kStorageImage},
                    {"params", 2, kUniformBuffer},
                    {"Values", 3, kStorageBuffer},
                    {"unusedCube", 5, kSampled}});
}

TEST(Reflect, StageIsTheCallersAndShaderWithoutBindingsIsEmpty) {
    expectBindings(reflect("engine/tonemap.frag", VK_SHADER_STAGE_FRAGMENT_BIT), VK_SHADER_STAGE_FRAGMENT_BIT,
                   {{"linearTex", 0, kSampled}});
    EXPECT_TRUE(reflect("engine/fullscreen.vert", VK_SHADER_STAGE_VERTEX_BIT).empty());
}

// gbuffer.vert and gbuffer.frag both declare the frame constants (gbuffer_common.glsl).
TEST(Reflect, MergeOrsTheStagesOfABindingBothShadersDeclare) {
    auto merged =
        gpu::mergeBindings(reflect("engine/gbuffer.vert", VK_SHADER_STAGE_VERTEX_BIT), "engine/gbuffer.vert",
                           reflect("engine/gbuffer.frag", VK_SHADER_STAGE_FRAGMENT_BIT), "engine/gbuffer.frag");
    ASSERT_EQ(merged.size(), 5u);
    expectBinding(merged[0], {"frame", 0, kUniformBuffer}, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);
    expectBinding(merged[1], {"baseColorTex", 1, kSampled}, VK_SHADER_STAGE_FRAGMENT_BIT);
    expectBinding(merged[4], {"emissiveTex", 4, kSampled}, VK_SHADER_STAGE_FRAGMENT_BIT);
}

// lighting.frag's binding 1 is albedoTex, gbuffer.frag's baseColorTex: one pipeline cannot hold both.
TEST(Reflect, MergeConflictThrowsNamingBothShaders) {
    auto a = reflect("engine/gbuffer.frag", VK_SHADER_STAGE_FRAGMENT_BIT);
    auto b = reflect("engine/lighting.frag", VK_SHADER_STAGE_FRAGMENT_BIT);
    try {
        gpu::mergeBindings(a, "engine/gbuffer.frag", b, "engine/lighting.frag");
        FAIL() << "expected std::logic_error";
    } catch (const std::logic_error& e) {
        std::string what = e.what();
        EXPECT_NE(what.find("engine/gbuffer.frag"), std::string::npos) << what;
        EXPECT_NE(what.find("engine/lighting.frag"), std::string::npos) << what;
    }
    // One name at two numbers is a conflict too.
    std::vector<gpu::ReflectedBinding> x{{"tex", 0, kSampled, 1, VK_SHADER_STAGE_VERTEX_BIT}};
    std::vector<gpu::ReflectedBinding> y{{"tex", 1, kSampled, 1, VK_SHADER_STAGE_FRAGMENT_BIT}};
    EXPECT_THROW(gpu::mergeBindings(x, "a.vert", y, "b.frag"), std::logic_error);
}

TEST(Reflect, GarbageIsALogicErrorNamingTheShader) {
    std::vector<uint32_t> words{0x07230203u, 0x00010000u, 0u, 1u, 0u};  // a header, no entry point
    try {
        gpu::reflectBindings(words, VK_SHADER_STAGE_COMPUTE_BIT, "bogus.comp");
        FAIL() << "expected std::logic_error";
    } catch (const std::logic_error& e) {
        EXPECT_NE(std::string(e.what()).find("bogus.comp"), std::string::npos) << e.what();
    }
}
