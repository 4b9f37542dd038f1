// Descriptor bindings read from SPIR-V (SPIRV-Cross's reflection). The shader's
// `layout(set = 0, binding = N) uniform ... name;` is the only declaration of a binding: pipelines
// build their set layout from this table and DescriptorWriter resolves names through it, so the
// numbers live in GLSL alone (STYLE.md, Shaders).
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace speculum::gpu {

struct ReflectedBinding {
    // The variable's name; for a block declared without an instance name, the block's type name
    // (`buffer ProbeBuffer { ... };` is "ProbeBuffer").
    std::string name;
    uint32_t binding = 0;
    VkDescriptorType type = VK_DESCRIPTOR_TYPE_MAX_ENUM;
    uint32_t count = 1;  // array size; 1 for a single descriptor
    VkShaderStageFlags stages = 0;
};

// Set 0's bindings of one SPIR-V module, sorted by binding number. Every binding the module
// declares is listed, whether the entry point uses it or not (see DescriptorWriter::push for
// why). `shader` names the module in errors. Throws std::logic_error for what the engine's
// single push-descriptor set cannot hold: a set other than 0, a descriptor kind other than
// combined image sampler, storage image, uniform or storage buffer, an unsized array, or two
// variables on one binding.
std::vector<ReflectedBinding> reflectBindings(std::span<const uint32_t> spirv, VkShaderStageFlagBits stage,
                                              const std::string& shader);

// One pipeline's table from two stages' (vertex and fragment). A binding both declare with the
// same name, kind and count is listed once with both stages; any other overlap (one number, two
// names or kinds; one name, two numbers) throws std::logic_error naming both shaders.
std::vector<ReflectedBinding> mergeBindings(const std::vector<ReflectedBinding>& a, const std::string& shaderA,
                                            const std::vector<ReflectedBinding>& b, const std::string& shaderB);

// "combined image sampler", "storage image", ...: for messages.
std::string_view descriptorTypeName(VkDescriptorType type);

}  // namespace speculum::gpu
