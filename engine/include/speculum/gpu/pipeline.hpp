// Shader modules and pipelines. Descriptors are push descriptors (VK_KHR_push_descriptor):
// a pipeline has one set (set 0) described by its bindings, and passes push it per draw or
// dispatch, so there are no descriptor pools to manage and no bindless (lavapipe lacks it).
// The bindings are declared once, in the shader: a pipeline reflects them from its SPIR-V
// (reflect.hpp) and DescriptorWriter writes them by the GLSL variable's name.
#pragma once

#include "speculum/gpu/context.hpp"
#include "speculum/gpu/reflect.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace speculum::gpu {

// Loads SPIR-V compiled at build time: name is relative to shaders/, e.g. "engine/gbuffer.vert".
Unique<VkShaderModule> loadShader(const Context& ctx, const std::string& name);
// The same file's words (for reflection).
std::vector<uint32_t> loadSpirv(const std::string& name);
std::string shaderDir();

// Layout shared by compute and graphics pipelines: one push-descriptor set + push constants.
class PipelineLayout {
public:
    PipelineLayout() = default;
    PipelineLayout(const Context& ctx, const std::vector<ReflectedBinding>& bindings, uint32_t pushConstantBytes,
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
    Pipeline(Unique<VkPipeline> p, PipelineLayout layout, VkPipelineBindPoint bind,
             std::vector<ReflectedBinding> bindings, std::string shader, std::string name)
        : pipeline_(std::move(p)),
          layout_(std::move(layout)),
          bind_(bind),
          bindings_(std::move(bindings)),
          shader_(std::move(shader)),
          name_(std::move(name)) {}
    VkPipeline get() const { return pipeline_; }
    VkPipelineLayout layout() const { return layout_.get(); }
    VkPipelineBindPoint bindPoint() const { return bind_; }
    void bind(VkCommandBuffer cmd) const { vkCmdBindPipeline(cmd, bind_, pipeline_); }
    // Set 0 as the shaders declare it, sorted by binding.
    const std::vector<ReflectedBinding>& bindings() const { return bindings_; }
    const ReflectedBinding* findBinding(std::string_view name) const;
    // The shader file(s), "reflections/trace.comp" or "engine/gbuffer.vert + engine/gbuffer.frag".
    const std::string& shader() const { return shader_; }
    const std::string& name() const { return name_; }

private:
    Unique<VkPipeline> pipeline_;
    PipelineLayout layout_;
    VkPipelineBindPoint bind_ = VK_PIPELINE_BIND_POINT_COMPUTE;
    std::vector<ReflectedBinding> bindings_;
    std::string shader_;
    std::string name_;
};

// The set layout comes from the shader's reflection (reflect.hpp).
Pipeline createComputePipeline(const Context& ctx, const std::string& shader, uint32_t pushConstantBytes,
                               const std::string& name, const std::vector<uint32_t>& constants = {});

struct GraphicsPipelineDesc {
    std::string vertexShader;
    std::string fragmentShader;  // empty: depth-only
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

// Builds push-descriptor writes for one pipeline by the shader's variable names
// (`.sampled("depthTex", view, sampler)`); the numbers and descriptor types come from the
// pipeline's reflection when push() resolves the names. Keeps the info structs alive until push().
class DescriptorWriter {
public:
    // A sampler2D, samplerCube, ... (combined image sampler); `layout`: the image's while it is read.
    DescriptorWriter& sampled(std::string_view name, VkImageView view, VkSampler sampler,
                              VkImageLayout layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    // An image2D, imageCube, ... in GENERAL.
    DescriptorWriter& storage(std::string_view name, VkImageView view);
    // A uniform or storage block; which one, the shader says.
    DescriptorWriter& buffer(std::string_view name, VkBuffer buffer, VkDeviceSize offset = 0,
                             VkDeviceSize range = VK_WHOLE_SIZE);
    // Throws std::logic_error, naming the pipeline, its shader and the binding, for a name the
    // shader does not declare, a name written twice, a call that does not fit the declared kind
    // (sampled() on an image2D) and a declared binding nothing wrote. Clears the writer.
    void push(const Context& ctx, VkCommandBuffer cmd, const Pipeline& pipeline);

private:
    enum class Kind { Sampled, Storage, Buffer };
    struct Entry {
        std::string name;
        Kind kind;
        VkDescriptorImageInfo image;
        VkDescriptorBufferInfo buffer;
    };
    std::vector<Entry> entries_;
};

}  // namespace speculum::gpu
