#include "speculum/gpu/reflect.hpp"

#include <spirv_cross/spirv_cross_c.h>

#include <algorithm>
#include <memory>
#include <stdexcept>

namespace speculum::gpu {
namespace {

// The C API's context owns everything it hands out; one per reflected module.
struct ContextDeleter {
    void operator()(spvc_context c) const { spvc_context_destroy(c); }
};
using SpvcContext = std::unique_ptr<std::remove_pointer_t<spvc_context>, ContextDeleter>;

[[noreturn]] void fail(const std::string& shader, const std::string& what) {
    throw std::logic_error("shader " + shader + ": " + what);
}

// The resource lists that are descriptors, with the type each becomes in the set layout.
struct Kind {
    spvc_resource_type resource;
    VkDescriptorType type;
};
constexpr Kind kKinds[] = {
    {SPVC_RESOURCE_TYPE_SAMPLED_IMAGE, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
    {SPVC_RESOURCE_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
    {SPVC_RESOURCE_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
    {SPVC_RESOURCE_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
};
// Lists that would need a descriptor type the engine does not write.
constexpr spvc_resource_type kUnsupported[] = {
    SPVC_RESOURCE_TYPE_SEPARATE_IMAGE, SPVC_RESOURCE_TYPE_SEPARATE_SAMPLERS, SPVC_RESOURCE_TYPE_SUBPASS_INPUT,
    SPVC_RESOURCE_TYPE_ACCELERATION_STRUCTURE, SPVC_RESOURCE_TYPE_ATOMIC_COUNTER};

ReflectedBinding reflectOne(spvc_compiler compiler, const spvc_reflected_resource& r, VkDescriptorType type,
                            VkShaderStageFlagBits stage, const std::string& shader) {
    // glslang names an anonymous block's variable "": its type's name (r.name for a block) is
    // the only name the GLSL gives it.
    std::string name = spvc_compiler_get_name(compiler, r.id);
    if (name.empty()) name = r.name;
    if (spvc_compiler_get_decoration(compiler, r.id, SpvDecorationDescriptorSet) != 0)
        fail(shader, "'" + name + "' is not in set 0 (pipelines have one push-descriptor set)");
    spvc_type t = spvc_compiler_get_type_handle(compiler, r.type_id);
    if ((type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER || type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE) &&
        spvc_type_get_image_dimension(t) == SpvDimBuffer)
        fail(shader, "'" + name + "' is a texel buffer, which DescriptorWriter does not write");
    uint32_t count = 1;
    for (unsigned d = 0; d < spvc_type_get_num_array_dimensions(t); ++d) {
        if (!spvc_type_array_dimension_is_literal(t, d) || spvc_type_get_array_dimension(t, d) == 0)
            fail(shader, "'" + name + "' is an unsized or specialized array");
        count *= spvc_type_get_array_dimension(t, d);
    }
    return {name, spvc_compiler_get_decoration(compiler, r.id, SpvDecorationBinding), type, count,
            VkShaderStageFlags(stage)};
}

}  // namespace

std::string_view descriptorTypeName(VkDescriptorType type) {
    switch (type) {
        case VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER:
            return "sampled image";
        case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
            return "storage image";
        case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER:
            return "uniform buffer";
        case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER:
            return "storage buffer";
        default:
            return "unsupported descriptor";
    }
}

std::vector<ReflectedBinding> reflectBindings(std::span<const uint32_t> spirv, VkShaderStageFlagBits stage,
                                              const std::string& shader) {
    spvc_context raw = nullptr;
    if (spvc_context_create(&raw) != SPVC_SUCCESS) throw std::runtime_error("spvc_context_create failed");
    SpvcContext context(raw);
    spvc_parsed_ir ir = nullptr;
    spvc_compiler compiler = nullptr;
    spvc_resources resources = nullptr;
    if (spvc_context_parse_spirv(raw, spirv.data(), spirv.size(), &ir) != SPVC_SUCCESS ||
        spvc_context_create_compiler(raw, SPVC_BACKEND_NONE, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP, &compiler) !=
            SPVC_SUCCESS ||
        spvc_compiler_create_shader_resources(compiler, &resources) != SPVC_SUCCESS)
        fail(shader, std::string("SPIR-V reflection failed: ") + spvc_context_get_last_error_string(raw));

    const spvc_reflected_resource* list = nullptr;
    size_t n = 0;
    for (spvc_resource_type unsupported : kUnsupported) {
        spvc_resources_get_resource_list_for_type(resources, unsupported, &list, &n);
        if (n)
            fail(shader, "'" + std::string(list[0].name) + "' has a descriptor type DescriptorWriter does not write");
    }
    std::vector<ReflectedBinding> out;
    for (const Kind& kind : kKinds) {
        spvc_resources_get_resource_list_for_type(resources, kind.resource, &list, &n);
        for (size_t i = 0; i < n; ++i) out.push_back(reflectOne(compiler, list[i], kind.type, stage, shader));
    }
    std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) { return x.binding < y.binding; });
    for (size_t i = 1; i < out.size(); ++i)
        if (out[i].binding == out[i - 1].binding)
            fail(shader,
                 "'" + out[i - 1].name + "' and '" + out[i].name + "' share binding " + std::to_string(out[i].binding));
    return out;
}

std::vector<ReflectedBinding> mergeBindings(const std::vector<ReflectedBinding>& a, const std::string& shaderA,
                                            const std::vector<ReflectedBinding>& b, const std::string& shaderB) {
    std::vector<ReflectedBinding> out = a;
    for (const ReflectedBinding& y : b) {
        auto same = std::find_if(out.begin(), out.end(),
                                 [&](const ReflectedBinding& x) { return x.binding == y.binding || x.name == y.name; });
        if (same == out.end()) {
            out.push_back(y);
            continue;
        }
        if (same->binding != y.binding || same->name != y.name || same->type != y.type || same->count != y.count)
            throw std::logic_error("shaders " + shaderA + " and " + shaderB + " disagree: " + shaderA + " declares '" +
                                   same->name + "' at binding " + std::to_string(same->binding) + " (" +
                                   std::string(descriptorTypeName(same->type)) + "), " + shaderB + " '" + y.name +
                                   "' at binding " + std::to_string(y.binding) + " (" +
                                   std::string(descriptorTypeName(y.type)) + ")");
        same->stages |= y.stages;
    }
    std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) { return x.binding < y.binding; });
    return out;
}

}  // namespace speculum::gpu
