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

void expectBinding(const gpu::ReflectedBinding& b, const std::string& name, uint32_t binding, VkDescriptorType type,
                   VkShaderStageFlags stages, uint32_t count = 1) {
    EXPECT_EQ(b.name, name);
    EXPECT_EQ(b.binding, binding) << name;
    EXPECT_EQ(b.type, type) << name;
    EXPECT_EQ(b.stages, stages) << name;
    EXPECT_EQ(b.count, count) << name;
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
    auto b = reflect("probes/debug.comp", VK_SHADER_STAGE_COMPUTE_BIT);
    ASSERT_EQ(b.size(), 5u);
    expectBinding(b[0], "depthTex", 0, kSampled, kCompute);
    expectBinding(b[1], "normalTex", 1, kSampled, kCompute);
    expectBinding(b[2], "ProbeBuffer", 2, kStorageBuffer, kCompute);
    expectBinding(b[3], "probeCubes", 3, kSampled, kCompute);
    expectBinding(b[4], "outImage", 4, kStorageImage, kCompute);
}

// tests/shaders/reflect_kinds.comp: every kind, an array, a named block (its instance name)
// and a binding main() never reads, which is listed: the table is the declaration.
TEST(Reflect, KindsArraysBlockNamesAndUnusedBindings) {
    auto b = reflect("tests/reflect_kinds.comp", VK_SHADER_STAGE_COMPUTE_BIT);
    ASSERT_EQ(b.size(), 5u);
    expectBinding(b[0], "textures", 0, kSampled, kCompute, 3);
    expectBinding(b[1], "target", 1, kStorageImage, kCompute);
    expectBinding(b[2], "params", 2, kUniformBuffer, kCompute);
    expectBinding(b[3], "Values", 3, kStorageBuffer, kCompute);
    expectBinding(b[4], "unusedCube", 5, kSampled, kCompute);
}

TEST(Reflect, StageIsTheCallersAndShaderWithoutBindingsIsEmpty) {
    auto frag = reflect("engine/tonemap.frag", VK_SHADER_STAGE_FRAGMENT_BIT);
    ASSERT_EQ(frag.size(), 1u);
    expectBinding(frag[0], "linearTex", 0, kSampled, VK_SHADER_STAGE_FRAGMENT_BIT);
    EXPECT_TRUE(reflect("engine/fullscreen.vert", VK_SHADER_STAGE_VERTEX_BIT).empty());
}

// gbuffer.vert and gbuffer.frag both declare the frame constants (gbuffer_common.glsl).
TEST(Reflect, MergeOrsTheStagesOfABindingBothShadersDeclare) {
    auto merged =
        gpu::mergeBindings(reflect("engine/gbuffer.vert", VK_SHADER_STAGE_VERTEX_BIT), "engine/gbuffer.vert",
                           reflect("engine/gbuffer.frag", VK_SHADER_STAGE_FRAGMENT_BIT), "engine/gbuffer.frag");
    ASSERT_EQ(merged.size(), 5u);
    expectBinding(merged[0], "frame", 0, kUniformBuffer, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);
    expectBinding(merged[1], "baseColorTex", 1, kSampled, VK_SHADER_STAGE_FRAGMENT_BIT);
    expectBinding(merged[4], "emissiveTex", 4, kSampled, VK_SHADER_STAGE_FRAGMENT_BIT);
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
