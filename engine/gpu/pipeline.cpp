#include "speculum/gpu/pipeline.hpp"

#include "speculum/core.hpp"
#include "speculum/scene.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace speculum::gpu {

std::string shaderDir() {
    // SPECULUM_SHADER_DIR in the environment lets an installed or relocated binary find its SPIR-V.
    if (const char* dir = std::getenv("SPECULUM_SHADER_DIR"); dir && *dir) return dir;
    return SPECULUM_SHADER_DIR;
}

std::vector<uint32_t> loadSpirv(const std::string& name) {
    std::string path = shaderDir() + "/" + name + ".spv";
    std::ifstream file(path, std::ios::binary);
    if (!file)
        throw Error(ExitCode::Failure, "shader " + path + " is missing: build the project (cmake --build build)");
    std::vector<char> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    if (bytes.empty() || bytes.size() % sizeof(uint32_t))
        throw Error(ExitCode::Failure, "shader " + path + " is not SPIR-V (size " + std::to_string(bytes.size()) + ")");
    std::vector<uint32_t> words(bytes.size() / sizeof(uint32_t));
    std::copy(bytes.begin(), bytes.end(), reinterpret_cast<char*>(words.data()));
    return words;
}

namespace {

Unique<VkShaderModule> createModule(const Context& ctx, const std::vector<uint32_t>& words, const std::string& name) {
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = words.size() * sizeof(uint32_t);
    info.pCode = words.data();
    VkShaderModule module;
    check(vkCreateShaderModule(ctx.device(), &info, nullptr, &module), ("vkCreateShaderModule " + name).c_str());
    return {ctx.device(), module, vkDestroyShaderModule};
}

}  // namespace

Unique<VkShaderModule> loadShader(const Context& ctx, const std::string& name) {
    return createModule(ctx, loadSpirv(name), name);
}

PipelineLayout::PipelineLayout(const Context& ctx, const std::vector<ReflectedBinding>& bindings,
                               uint32_t pushConstantBytes, VkShaderStageFlags pushStages) {
    std::vector<VkDescriptorSetLayoutBinding> b;
    for (const ReflectedBinding& x : bindings) b.push_back({x.binding, x.type, x.count, x.stages, nullptr});
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
    setInfo.bindingCount = static_cast<uint32_t>(b.size());
    setInfo.pBindings = b.data();
    VkDescriptorSetLayout set;
    check(vkCreateDescriptorSetLayout(ctx.device(), &setInfo, nullptr, &set), "vkCreateDescriptorSetLayout");
    setLayout_ = Unique<VkDescriptorSetLayout>(ctx.device(), set, vkDestroyDescriptorSetLayout);

    VkPushConstantRange range{pushStages, 0, pushConstantBytes};
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.setLayoutCount = 1;
    info.pSetLayouts = &set;
    info.pushConstantRangeCount = pushConstantBytes ? 1 : 0;
    info.pPushConstantRanges = &range;
    VkPipelineLayout layout;
    check(vkCreatePipelineLayout(ctx.device(), &info, nullptr, &layout), "vkCreatePipelineLayout");
    layout_ = Unique<VkPipelineLayout>(ctx.device(), layout, vkDestroyPipelineLayout);
}

namespace {

// Specialization constants constant_id 0, 1, ... as consecutive uint32 values.
struct Specialization {
    std::vector<VkSpecializationMapEntry> entries;
    VkSpecializationInfo info{};

    explicit Specialization(const std::vector<uint32_t>& values) {
        for (uint32_t i = 0; i < values.size(); ++i)
            entries.push_back({i, uint32_t(i * sizeof(uint32_t)), sizeof(uint32_t)});
        info.mapEntryCount = uint32_t(entries.size());
        info.pMapEntries = entries.data();
        info.dataSize = values.size() * sizeof(uint32_t);
        info.pData = values.data();
    }
    const VkSpecializationInfo* get() const { return entries.empty() ? nullptr : &info; }
};

}  // namespace

Pipeline createComputePipeline(const Context& ctx, const std::string& shader, uint32_t pushConstantBytes,
                               const std::string& name, const std::vector<uint32_t>& constants) {
    std::vector<uint32_t> words = loadSpirv(shader);
    std::vector<ReflectedBinding> bindings = reflectBindings(words, VK_SHADER_STAGE_COMPUTE_BIT, shader);
    PipelineLayout layout(ctx, bindings, pushConstantBytes, VK_SHADER_STAGE_COMPUTE_BIT);
    Unique<VkShaderModule> module = createModule(ctx, words, shader);
    Specialization spec(constants);
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = module;
    info.stage.pName = "main";
    info.stage.pSpecializationInfo = spec.get();
    info.layout = layout.get();
    VkPipeline p;
    check(vkCreateComputePipelines(ctx.device(), VK_NULL_HANDLE, 1, &info, nullptr, &p),
          ("vkCreateComputePipelines " + name).c_str());
    ctx.setName(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<uint64_t>(p), name);
    return {Unique<VkPipeline>(ctx.device(), p, vkDestroyPipeline),
            std::move(layout),
            VK_PIPELINE_BIND_POINT_COMPUTE,
            std::move(bindings),
            shader,
            name};
}

Pipeline createGraphicsPipeline(const Context& ctx, const GraphicsPipelineDesc& d) {
    std::vector<uint32_t> vsWords = loadSpirv(d.vertexShader);
    std::vector<ReflectedBinding> bindings = reflectBindings(vsWords, VK_SHADER_STAGE_VERTEX_BIT, d.vertexShader);
    std::string shaders = d.vertexShader;
    std::vector<uint32_t> fsWords;
    if (!d.fragmentShader.empty()) {
        fsWords = loadSpirv(d.fragmentShader);
        bindings =
            mergeBindings(bindings, d.vertexShader,
                          reflectBindings(fsWords, VK_SHADER_STAGE_FRAGMENT_BIT, d.fragmentShader), d.fragmentShader);
        shaders += " + " + d.fragmentShader;
    }
    PipelineLayout layout(ctx, bindings, d.pushConstantBytes,
                          VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);
    Unique<VkShaderModule> vs = createModule(ctx, vsWords, d.vertexShader);
    Unique<VkShaderModule> fs;
    std::vector<VkPipelineShaderStageCreateInfo> stages(1, {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO});
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = vs;
    stages[0].pName = "main";
    Specialization spec(d.fragmentConstants);
    if (!d.fragmentShader.empty()) {
        fs = createModule(ctx, fsWords, d.fragmentShader);
        VkPipelineShaderStageCreateInfo f{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        f.stage = VK_SHADER_STAGE_FRAGMENT_BIT;
        f.module = fs;
        f.pName = "main";
        f.pSpecializationInfo = spec.get();
        stages.push_back(f);
    }

    VkVertexInputBindingDescription vb{0, sizeof(Vertex), VK_VERTEX_INPUT_RATE_VERTEX};
    VkVertexInputAttributeDescription attrs[] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
        {2, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(Vertex, tangent)},
        {3, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv)},
    };
    VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    if (d.vertexInput) {
        vi.vertexBindingDescriptionCount = 1;
        vi.pVertexBindingDescriptions = &vb;
        vi.vertexAttributeDescriptionCount = 4;
        vi.pVertexAttributeDescriptions = attrs;
    }
    VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    vp.viewportCount = 1;
    vp.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    rs.polygonMode = VK_POLYGON_MODE_FILL;
    rs.cullMode = d.cull;
    // glTF fronts are counter-clockwise. Our projections flip Y for Vulkan's downward clip
    // space, and Vulkan's facing rule is written for a downward framebuffer Y, so a triangle
    // that looks counter-clockwise on screen stays counter-clockwise here.
    rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    rs.depthBiasEnable = d.depthBias;
    rs.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    ds.depthTestEnable = d.depthTest;
    ds.depthWriteEnable = d.depthWrite;
    ds.depthCompareOp = d.depthCompare;
    std::vector<VkPipelineColorBlendAttachmentState> blends(d.colorFormats.size());
    for (auto& b : blends) b.colorWriteMask = 0xf;
    VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    cb.attachmentCount = static_cast<uint32_t>(blends.size());
    cb.pAttachments = blends.data();
    std::vector<VkDynamicState> dyn{VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    if (d.depthBias) dyn.push_back(VK_DYNAMIC_STATE_DEPTH_BIAS);
    VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dy.dynamicStateCount = static_cast<uint32_t>(dyn.size());
    dy.pDynamicStates = dyn.data();
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.colorAttachmentCount = static_cast<uint32_t>(d.colorFormats.size());
    rendering.pColorAttachmentFormats = d.colorFormats.data();
    rendering.depthAttachmentFormat = d.depthFormat;

    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.pNext = d.renderPass ? nullptr : &rendering;
    info.renderPass = d.renderPass;
    info.stageCount = static_cast<uint32_t>(stages.size());
    info.pStages = stages.data();
    info.pVertexInputState = &vi;
    info.pInputAssemblyState = &ia;
    info.pViewportState = &vp;
    info.pRasterizationState = &rs;
    info.pMultisampleState = &ms;
    info.pDepthStencilState = &ds;
    info.pColorBlendState = &cb;
    info.pDynamicState = &dy;
    info.layout = layout.get();
    VkPipeline p;
    check(vkCreateGraphicsPipelines(ctx.device(), VK_NULL_HANDLE, 1, &info, nullptr, &p),
          ("vkCreateGraphicsPipelines " + d.name).c_str());
    ctx.setName(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<uint64_t>(p), d.name);
    return {Unique<VkPipeline>(ctx.device(), p, vkDestroyPipeline),
            std::move(layout),
            VK_PIPELINE_BIND_POINT_GRAPHICS,
            std::move(bindings),
            shaders,
            d.name};
}

const ReflectedBinding* Pipeline::findBinding(std::string_view name) const {
    auto it =
        std::find_if(bindings_.begin(), bindings_.end(), [&](const ReflectedBinding& b) { return b.name == name; });
    return it == bindings_.end() ? nullptr : &*it;
}

DescriptorWriter& DescriptorWriter::sampled(std::string_view name, VkImageView view, VkSampler sampler,
                                            VkImageLayout layout) {
    entries_.push_back({std::string(name), Kind::Sampled, {sampler, view, layout}, {}});
    return *this;
}

DescriptorWriter& DescriptorWriter::storage(std::string_view name, VkImageView view) {
    entries_.push_back({std::string(name), Kind::Storage, {VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL}, {}});
    return *this;
}

DescriptorWriter& DescriptorWriter::buffer(std::string_view name, VkBuffer buffer, VkDeviceSize offset,
                                           VkDeviceSize range) {
    entries_.push_back({std::string(name), Kind::Buffer, {}, {buffer, offset, range}});
    return *this;
}

// Names resolve against the reflection of the SPIR-V as compiled (glslang -g, unoptimised),
// which lists every binding the GLSL declares, used or not: the table follows the GLSL text, and
// one table serves every specialization of a shader (a variant that skips a binding still
// declares it). So a writer writes exactly the bindings the shader declares, all of them, each
// once: a declared but unused binding must be written too (binding a placeholder, as the
// reflections passes do), and a binding an optimiser removed from the SPIR-V is unknown.
void DescriptorWriter::push(const Context& ctx, VkCommandBuffer cmd, const Pipeline& pipeline) {
    auto fits = [](VkDescriptorType type, Kind kind) {
        switch (type) {
            case VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER:
                return kind == Kind::Sampled;
            case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
                return kind == Kind::Storage;
            case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER:
            case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER:
                return kind == Kind::Buffer;
            default:
                return false;
        }
    };
    auto error = [&](const std::string& what) {
        return std::logic_error("DescriptorWriter, pipeline '" + pipeline.name() + "' (" + pipeline.shader() +
                                "): " + what);
    };
    const std::vector<ReflectedBinding>& table = pipeline.bindings();
    std::vector<bool> written(table.size(), false);
    std::vector<VkWriteDescriptorSet> writes;
    writes.reserve(entries_.size());
    for (const Entry& e : entries_) {
        const ReflectedBinding* b = pipeline.findBinding(e.name);
        if (!b) throw error("the shader declares no binding '" + e.name + "'");
        size_t index = size_t(b - table.data());
        if (written[index]) throw error("'" + e.name + "' is written twice");
        written[index] = true;
        if (!fits(b->type, e.kind))
            throw error("'" + e.name + "' (binding " + std::to_string(b->binding) + ") is a " +
                        std::string(descriptorTypeName(b->type)) + ", written as " +
                        (e.kind == Kind::Sampled   ? "sampled()"
                         : e.kind == Kind::Storage ? "storage()"
                                                   : "buffer()"));
        if (b->count != 1)
            throw error("'" + e.name + "' is an array of " + std::to_string(b->count) +
                        "; DescriptorWriter writes single descriptors");
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstBinding = b->binding;
        w.descriptorCount = 1;
        w.descriptorType = b->type;
        if (e.kind == Kind::Buffer)
            w.pBufferInfo = &e.buffer;
        else
            w.pImageInfo = &e.image;
        writes.push_back(w);
    }
    for (size_t i = 0; i < table.size(); ++i)
        if (!written[i])
            throw error("nothing wrote '" + table[i].name + "' (binding " + std::to_string(table[i].binding) + ", " +
                        std::string(descriptorTypeName(table[i].type)) + ")");
    ctx.cmdPushDescriptorSet(cmd, pipeline.bindPoint(), pipeline.layout(), 0, static_cast<uint32_t>(writes.size()),
                             writes.data());
    entries_.clear();
}

}  // namespace speculum::gpu
