// Shader modules and pipelines. Descriptors are push descriptors (VK_KHR_push_descriptor):
// a pipeline has one set (set 0) described by its bindings, and passes push it per draw or
// dispatch, so there are no descriptor pools to manage and no bindless (lavapipe lacks it).
#pragma once

#include "speculum/gpu/context.hpp"

#include <string>
#include <vector>

namespace speculum::gpu {

// Loads SPIR-V compiled at build time: name is relative to shaders/, e.g. "engine/gbuffer.vert".
Unique<VkShaderModule> loadShader(const Context& ctx, const std::string& name);
std::string shaderDir();

struct Binding {
    uint32_t binding;
    VkDescriptorType type;
    VkShaderStageFlags stages;
    uint32_t count = 1;
};

// Layout shared by compute and graphics pipelines: one push-descriptor set + push constants.
class PipelineLayout {
public:
    PipelineLayout() = default;
    PipelineLayout(const Context& ctx, const std::vector<Binding>& bindings, uint32_t pushConstantBytes,
                   VkShaderStageFlags pushStages);
    VkPipelineLayout get() const { return layout_; }
    VkDescriptorSetLayout setLayout() const { return setLayout_; }

private:
    Unique<VkDescriptorSetLayout> setLayout_;
    Unique<VkPipelineLayout> layout_;
};

class Pipeline {
public:
    Pipeline() = default;
    Pipeline(Unique<VkPipeline> p, PipelineLayout layout, VkPipelineBindPoint bind)
        : pipeline_(std::move(p)), layout_(std::move(layout)), bind_(bind) {}
    VkPipeline get() const { return pipeline_; }
    VkPipelineLayout layout() const { return layout_.get(); }
    VkPipelineBindPoint bindPoint() const { return bind_; }
    void bind(VkCommandBuffer cmd) const { vkCmdBindPipeline(cmd, bind_, pipeline_); }

private:
    Unique<VkPipeline> pipeline_;
    PipelineLayout layout_;
    VkPipelineBindPoint bind_ = VK_PIPELINE_BIND_POINT_COMPUTE;
};

Pipeline createComputePipeline(const Context& ctx, const std::string& shader, const std::vector<Binding>& bindings,
                               uint32_t pushConstantBytes, const std::string& name,
                               const std::vector<uint32_t>& constants = {});

struct GraphicsPipelineDesc {
    std::string vertexShader;
    std::string fragmentShader;  // empty: depth-only
    std::vector<Binding> bindings;
    uint32_t pushConstantBytes = 0;
    std::vector<VkFormat> colorFormats;
    VkFormat depthFormat = VK_FORMAT_UNDEFINED;
    bool depthTest = true;
    bool depthWrite = true;
    VkCompareOp depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;  // reversed-Z
    VkCullModeFlags cull = VK_CULL_MODE_BACK_BIT;
    bool vertexInput = true;  // engine Vertex layout (pos, normal, tangent, uv); false: fullscreen
    bool depthBias = false;
    // Values of the fragment shader's specialization constants (constant_id 0, 1, ...).
    std::vector<uint32_t> fragmentConstants;
    std::string name;
    // A render pass (subpass 0) for a pipeline drawn inside one (the editor's ImGui pass); null:
    // dynamic rendering with colorFormats and depthFormat.
    VkRenderPass renderPass = VK_NULL_HANDLE;
};
Pipeline createGraphicsPipeline(const Context& ctx, const GraphicsPipelineDesc& desc);

// Builds push-descriptor writes for one pipeline; keeps the info structs alive until push().
class DescriptorWriter {
public:
    DescriptorWriter& image(uint32_t binding, VkDescriptorType type, VkImageView view, VkImageLayout layout,
                            VkSampler sampler = VK_NULL_HANDLE);
    DescriptorWriter& sampled(uint32_t binding, VkImageView view, VkSampler sampler) {
        return image(binding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, view,
                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, sampler);
    }
    DescriptorWriter& storage(uint32_t binding, VkImageView view) {
        return image(binding, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, view, VK_IMAGE_LAYOUT_GENERAL);
    }
    DescriptorWriter& buffer(uint32_t binding, VkDescriptorType type, VkBuffer buffer, VkDeviceSize offset = 0,
                             VkDeviceSize range = VK_WHOLE_SIZE);
    void push(const Context& ctx, VkCommandBuffer cmd, const Pipeline& pipeline);

private:
    struct Entry {
        uint32_t binding;
        VkDescriptorType type;
        VkDescriptorImageInfo image;
        VkDescriptorBufferInfo buffer;
    };
    std::vector<Entry> entries_;
};

}  // namespace speculum::gpu
