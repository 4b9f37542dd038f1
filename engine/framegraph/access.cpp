// Stage, access and layout implied by each usage. Raster passes may touch a shader resource
// from the vertex or the fragment stage; the graph does not know which, so it waits on and
// makes visible to both (VERTEX_SHADER | FRAGMENT_SHADER). Transfer passes only record copies,
// so a shader usage there (rejected by the builder) maps to ALL_COMMANDS.
#include "framegraph/graph_impl.hpp"

namespace speculum {
namespace {

VkPipelineStageFlags2 shaderStages(PassType type) {
    switch (type) {
    case PassType::Raster:
        return VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
    case PassType::Compute: return VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    case PassType::Transfer: return VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    }
    return VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
}

constexpr VkPipelineStageFlags2 kDepthStages =
    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;

}  // namespace

AccessInfo accessOf(TextureUsage usage, PassType type) {
    switch (usage) {
    case TextureUsage::ColorAttachment:
        return {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, true};
    case TextureUsage::DepthAttachment:
        return {kDepthStages,
                VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, true};
    case TextureUsage::DepthRead:
        return {kDepthStages, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
                VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL, false};
    case TextureUsage::Sampled:
        return {shaderStages(type), VK_ACCESS_2_SHADER_SAMPLED_READ_BIT,
                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, false};
    case TextureUsage::StorageRead:
        return {shaderStages(type), VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                VK_IMAGE_LAYOUT_GENERAL, false};
    case TextureUsage::StorageWrite:
        return {shaderStages(type), VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                VK_IMAGE_LAYOUT_GENERAL, true};
    case TextureUsage::TransferSrc:
        return {VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, false};
    case TextureUsage::TransferDst:
        return {VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, true};
    case TextureUsage::Present:
        // Presentation waits on a semaphore, not on a pipeline stage.
        return {VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, false};
    }
    return {};
}

AccessInfo accessOf(BufferUsage usage, PassType type) {
    const VkImageLayout none = VK_IMAGE_LAYOUT_UNDEFINED;
    switch (usage) {
    case BufferUsage::Uniform:
        return {shaderStages(type), VK_ACCESS_2_UNIFORM_READ_BIT, none, false};
    case BufferUsage::StorageRead:
        return {shaderStages(type), VK_ACCESS_2_SHADER_STORAGE_READ_BIT, none, false};
    case BufferUsage::StorageWrite:
        return {shaderStages(type), VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, none, true};
    case BufferUsage::TransferSrc:
        return {VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, none, false};
    case BufferUsage::TransferDst:
        return {VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, none, true};
    case BufferUsage::Vertex:
        return {VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT,
                VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT, none, false};
    case BufferUsage::Index:
        return {VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, VK_ACCESS_2_INDEX_READ_BIT, none, false};
    case BufferUsage::Indirect:
        return {VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT,
                none, false};
    }
    return {};
}

VkImageUsageFlags imageUsageOf(TextureUsage usage) {
    switch (usage) {
    case TextureUsage::ColorAttachment: return VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    case TextureUsage::DepthAttachment:
    case TextureUsage::DepthRead: return VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    case TextureUsage::Sampled: return VK_IMAGE_USAGE_SAMPLED_BIT;
    case TextureUsage::StorageRead:
    case TextureUsage::StorageWrite: return VK_IMAGE_USAGE_STORAGE_BIT;
    case TextureUsage::TransferSrc: return VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    case TextureUsage::TransferDst: return VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    case TextureUsage::Present: return 0;
    }
    return 0;
}

VkBufferUsageFlags bufferUsageOf(BufferUsage usage) {
    switch (usage) {
    case BufferUsage::Uniform: return VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT;
    case BufferUsage::StorageRead:
    case BufferUsage::StorageWrite: return VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    case BufferUsage::TransferSrc: return VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    case BufferUsage::TransferDst: return VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    case BufferUsage::Vertex: return VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
    case BufferUsage::Index: return VK_BUFFER_USAGE_INDEX_BUFFER_BIT;
    case BufferUsage::Indirect: return VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
    }
    return 0;
}

const char* usageName(TextureUsage usage) {
    switch (usage) {
    case TextureUsage::ColorAttachment: return "ColorAttachment";
    case TextureUsage::DepthAttachment: return "DepthAttachment";
    case TextureUsage::DepthRead: return "DepthRead";
    case TextureUsage::Sampled: return "Sampled";
    case TextureUsage::StorageRead: return "StorageRead";
    case TextureUsage::StorageWrite: return "StorageWrite";
    case TextureUsage::TransferSrc: return "TransferSrc";
    case TextureUsage::TransferDst: return "TransferDst";
    case TextureUsage::Present: return "Present";
    }
    return "?";
}

const char* usageName(BufferUsage usage) {
    switch (usage) {
    case BufferUsage::Uniform: return "Uniform";
    case BufferUsage::StorageRead: return "StorageRead";
    case BufferUsage::StorageWrite: return "StorageWrite";
    case BufferUsage::TransferSrc: return "TransferSrc";
    case BufferUsage::TransferDst: return "TransferDst";
    case BufferUsage::Vertex: return "Vertex";
    case BufferUsage::Index: return "Index";
    case BufferUsage::Indirect: return "Indirect";
    }
    return "?";
}

const char* layoutName(VkImageLayout layout) {
    switch (layout) {
    case VK_IMAGE_LAYOUT_UNDEFINED: return "UNDEFINED";
    case VK_IMAGE_LAYOUT_GENERAL: return "GENERAL";
    case VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL: return "COLOR_ATTACHMENT_OPTIMAL";
    case VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL: return "DEPTH_ATTACHMENT_OPTIMAL";
    case VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL: return "DEPTH_READ_ONLY_OPTIMAL";
    case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL: return "SHADER_READ_ONLY_OPTIMAL";
    case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL: return "TRANSFER_SRC_OPTIMAL";
    case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL: return "TRANSFER_DST_OPTIMAL";
    case VK_IMAGE_LAYOUT_PRESENT_SRC_KHR: return "PRESENT_SRC_KHR";
    default: return "OTHER";
    }
}

VkImageAspectFlags aspectOf(VkFormat format) {
    switch (format) {
    case VK_FORMAT_D16_UNORM:
    case VK_FORMAT_X8_D24_UNORM_PACK32:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_D16_UNORM_S8_UINT:
    case VK_FORMAT_D24_UNORM_S8_UINT:
    case VK_FORMAT_D32_SFLOAT_S8_UINT: return VK_IMAGE_ASPECT_DEPTH_BIT;
    case VK_FORMAT_S8_UINT: return VK_IMAGE_ASPECT_STENCIL_BIT;
    default: return VK_IMAGE_ASPECT_COLOR_BIT;
    }
}

}  // namespace speculum
