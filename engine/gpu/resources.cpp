#include "speculum/gpu/resources.hpp"

#include "speculum/core.hpp"
#include "speculum/framegraph.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>

namespace speculum::gpu {
namespace {

std::atomic<uint64_t> gPersistentBytes{0};

Unique<VkDeviceMemory> allocate(const Context& ctx, const VkMemoryRequirements& req, VkMemoryPropertyFlags flags) {
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = req.size;
    info.memoryTypeIndex = ctx.findMemoryType(req.memoryTypeBits, flags);
    VkDeviceMemory memory;
    check(vkAllocateMemory(ctx.device(), &info, nullptr, &memory), "vkAllocateMemory");
    return {ctx.device(), memory, vkFreeMemory};
}

float halfToFloat(uint16_t h) {
    uint32_t sign = (h & 0x8000u) << 16, exp = (h >> 10) & 0x1f, mant = h & 0x3ff;
    uint32_t bits;
    if (exp == 0) {
        if (mant == 0) {
            bits = sign;
        } else {  // subnormal: renormalise
            exp = 127 - 15 + 1;
            while (!(mant & 0x400)) {
                mant <<= 1;
                --exp;
            }
            bits = sign | (exp << 23) | ((mant & 0x3ff) << 13);
        }
    } else if (exp == 31) {
        bits = sign | 0x7f800000u | (mant << 13);
    } else {
        bits = sign | ((exp + 127 - 15) << 23) | (mant << 13);
    }
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

// Channel count and per-channel decoder for the formats readImageRGBA understands.
struct FormatLayout {
    int channels = 0;
    enum Kind { Unorm8, Half, Float } kind = Unorm8;
};
FormatLayout layoutOf(VkFormat f) {
    switch (f) {
        case VK_FORMAT_R8_UNORM: return {1, FormatLayout::Unorm8};
        case VK_FORMAT_R8G8_UNORM: return {2, FormatLayout::Unorm8};
        case VK_FORMAT_R8G8B8A8_UNORM:
        case VK_FORMAT_R8G8B8A8_SRGB: return {4, FormatLayout::Unorm8};
        case VK_FORMAT_R16_SFLOAT: return {1, FormatLayout::Half};
        case VK_FORMAT_R16G16_SFLOAT: return {2, FormatLayout::Half};
        case VK_FORMAT_R16G16B16A16_SFLOAT: return {4, FormatLayout::Half};
        case VK_FORMAT_R32_SFLOAT:
        case VK_FORMAT_D32_SFLOAT: return {1, FormatLayout::Float};
        case VK_FORMAT_R32G32_SFLOAT: return {2, FormatLayout::Float};
        case VK_FORMAT_R32G32B32A32_SFLOAT: return {4, FormatLayout::Float};
        default: return {};
    }
}

}  // namespace

uint64_t persistentBytes() { return gPersistentBytes.load(); }

AllocationCounter::AllocationCounter(uint64_t bytes) : bytes_(bytes) { gPersistentBytes += bytes; }
AllocationCounter& AllocationCounter::operator=(AllocationCounter&& o) noexcept {
    if (this != &o) {
        gPersistentBytes -= bytes_;
        bytes_ = std::exchange(o.bytes_, 0);
    }
    return *this;
}
AllocationCounter::~AllocationCounter() { gPersistentBytes -= bytes_; }

size_t bytesPerPixel(VkFormat format) {
    FormatLayout l = layoutOf(format);
    if (l.channels == 0) throw Error(ExitCode::Failure, "bytesPerPixel: unsupported format " + std::to_string(format));
    size_t per = l.kind == FormatLayout::Unorm8 ? 1 : l.kind == FormatLayout::Half ? 2 : 4;
    return per * static_cast<size_t>(l.channels);
}

Buffer::Buffer(const Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, bool hostVisible,
               const std::string& name)
    : size_(size) {
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = std::max<VkDeviceSize>(size, 4);
    info.usage = usage;
    VkBuffer b;
    check(vkCreateBuffer(ctx.device(), &info, nullptr, &b), "vkCreateBuffer");
    buffer_ = Unique<VkBuffer>(ctx.device(), b, vkDestroyBuffer);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.device(), b, &req);
    VkMemoryPropertyFlags flags = hostVisible
                                      ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                      : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    memory_ = allocate(ctx, req, flags);
    counter_ = AllocationCounter(req.size);
    check(vkBindBufferMemory(ctx.device(), b, memory_, 0), "vkBindBufferMemory");
    if (hostVisible) check(vkMapMemory(ctx.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
    ctx.setName(VK_OBJECT_TYPE_BUFFER, reinterpret_cast<uint64_t>(b), name);
}

Image::Image(const Context& ctx, const ImageDesc& desc, const std::string& name) : desc_(desc) {
    const auto& limits = ctx.properties().limits;
    uint32_t maxDim = desc.cube ? limits.maxImageDimensionCube : limits.maxImageDimension2D;
    if (desc.width == 0 || desc.height == 0 || desc.width > maxDim || desc.height > maxDim)
        throw argumentError("image '" + name + "' size " + std::to_string(desc.width) + "x" +
                            std::to_string(desc.height) + " is outside 1.." + std::to_string(maxDim));
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.flags = desc.cube ? VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT : 0;
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = desc.format;
    info.extent = {desc.width, desc.height, 1};
    info.mipLevels = desc.mips;
    info.arrayLayers = desc.layers;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = desc.usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImage img;
    check(vkCreateImage(ctx.device(), &info, nullptr, &img), "vkCreateImage");
    image_ = Unique<VkImage>(ctx.device(), img, vkDestroyImage);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx.device(), img, &req);
    memory_ = allocate(ctx, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    counter_ = AllocationCounter(req.size);
    check(vkBindImageMemory(ctx.device(), img, memory_, 0), "vkBindImageMemory");
    ctx.setName(VK_OBJECT_TYPE_IMAGE, reinterpret_cast<uint64_t>(img), name);

    auto makeView = [&](uint32_t baseMip, uint32_t mips) {
        VkImageViewCreateInfo v{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        v.image = img;
        v.viewType = desc.cube ? (desc.layers > 6 ? VK_IMAGE_VIEW_TYPE_CUBE_ARRAY : VK_IMAGE_VIEW_TYPE_CUBE)
                               : (desc.layers > 1 ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D);
        v.format = desc.format;
        v.subresourceRange = {aspect(), baseMip, mips, 0, desc.layers};
        VkImageView view;
        check(vkCreateImageView(ctx.device(), &v, nullptr, &view), "vkCreateImageView");
        return Unique<VkImageView>(ctx.device(), view, vkDestroyImageView);
    };
    view_ = makeView(0, desc.mips);
    for (uint32_t m = 0; m < desc.mips; ++m) mipViews_.push_back(makeView(m, 1));
}

VkImageAspectFlags Image::aspect() const {
    return aspectOf(desc_.format);
}

Unique<VkSampler> createSampler(const Context& ctx, VkFilter filter, VkSamplerAddressMode address, bool mipmaps,
                                VkSamplerReductionMode reduction) {
    VkSamplerReductionModeCreateInfo red{VK_STRUCTURE_TYPE_SAMPLER_REDUCTION_MODE_CREATE_INFO};
    red.reductionMode = reduction;
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    if (reduction != VK_SAMPLER_REDUCTION_MODE_WEIGHTED_AVERAGE) info.pNext = &red;
    info.magFilter = filter;
    info.minFilter = filter;
    info.mipmapMode = filter == VK_FILTER_LINEAR ? VK_SAMPLER_MIPMAP_MODE_LINEAR : VK_SAMPLER_MIPMAP_MODE_NEAREST;
    info.addressModeU = info.addressModeV = info.addressModeW = address;
    info.maxLod = mipmaps ? VK_LOD_CLAMP_NONE : 0.0f;
    VkSampler s;
    check(vkCreateSampler(ctx.device(), &info, nullptr, &s), "vkCreateSampler");
    return {ctx.device(), s, vkDestroySampler};
}

void transition(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
                VkImageLayout to, uint32_t baseMip, uint32_t mips, uint32_t baseLayer, uint32_t layers) {
    VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    b.srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    b.srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT;
    b.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    b.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {aspect, baseMip, mips, baseLayer, layers};
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = 1;
    dep.pImageMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &dep);
}

HistoryImages::HistoryImages(const Context& ctx, ImageDesc desc, const std::string& name) {
    desc.usage |= VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    images_[0] = Image(ctx, desc, name + ".0");
    images_[1] = Image(ctx, desc, name + ".1");
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        for (const Image& image : images_) {
            VkImageSubresourceRange all{image.aspect(), 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS};
            transition(cmd, image.get(), image.aspect(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
            if (image.aspect() & VK_IMAGE_ASPECT_DEPTH_BIT) {
                VkClearDepthStencilValue zero{};
                vkCmdClearDepthStencilImage(cmd, image.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &all);
            } else {
                VkClearColorValue zero{};
                vkCmdClearColorImage(cmd, image.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &all);
            }
            transition(cmd, image.get(), image.aspect(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                       VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        }
    });
    TextureDesc td{.width = desc.width, .height = desc.height, .format = desc.format, .mips = desc.mips,
                   .layers = desc.layers, .cube = desc.cube};
    history_ = History(td, images_[0].get(), images_[1].get(), desc.usage);
}

Buffer uploadBuffer(const Context& ctx, std::span<const std::byte> data, VkBufferUsageFlags usage,
                    const std::string& name) {
    Buffer staging(ctx, data.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, name + ".staging");
    if (!data.empty()) std::memcpy(staging.mapped(), data.data(), data.size());
    Buffer dst(ctx, data.size(), usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false, name);
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, 0, std::max<VkDeviceSize>(data.size(), 4)};
        if (!data.empty()) vkCmdCopyBuffer(cmd, staging.get(), dst.get(), 1, &region);
    });
    return dst;
}

void uploadImage(const Context& ctx, const Image& image, std::span<const std::byte> data, bool generateMips) {
    const ImageDesc& d = image.desc();
    Buffer staging(ctx, data.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, "gpu.upload.staging");
    std::memcpy(staging.mapped(), data.data(), data.size());
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        VkImageAspectFlags aspect = image.aspect();
        transition(cmd, image.get(), aspect, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {aspect, 0, 0, d.layers};
        copy.imageExtent = {d.width, d.height, 1};
        vkCmdCopyBufferToImage(cmd, staging.get(), image.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
        uint32_t mips = generateMips ? d.mips : 1;
        for (uint32_t m = 1; m < mips; ++m) {
            transition(cmd, image.get(), aspect, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                       VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, m - 1, 1);
            VkImageBlit blit{};
            blit.srcSubresource = {aspect, m - 1, 0, d.layers};
            blit.srcOffsets[1] = {int32_t(std::max(1u, d.width >> (m - 1))), int32_t(std::max(1u, d.height >> (m - 1))), 1};
            blit.dstSubresource = {aspect, m, 0, d.layers};
            blit.dstOffsets[1] = {int32_t(std::max(1u, d.width >> m)), int32_t(std::max(1u, d.height >> m)), 1};
            vkCmdBlitImage(cmd, image.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image.get(),
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
        }
        if (mips > 1)
            transition(cmd, image.get(), aspect, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                       VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, 0, mips - 1);
        transition(cmd, image.get(), aspect, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                   VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, mips - 1, VK_REMAINING_MIP_LEVELS);
    });
}

std::vector<float> readImageRGBA(const Context& ctx, VkImage image, const ImageDesc& desc, VkImageLayout layout,
                                 uint32_t mip, uint32_t layer) {
    uint32_t w = std::max(1u, desc.width >> mip), h = std::max(1u, desc.height >> mip);
    size_t bpp = bytesPerPixel(desc.format);
    Buffer staging(ctx, VkDeviceSize(w) * h * bpp, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, "gpu.readback");
    VkImageAspectFlags aspect = aspectOf(desc.format);
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        transition(cmd, image, aspect, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, mip, 1, layer, 1);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {aspect, mip, layer, 1};
        copy.imageExtent = {w, h, 1};
        vkCmdCopyImageToBuffer(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.get(), 1, &copy);
        transition(cmd, image, aspect, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout, mip, 1, layer, 1);
    });
    return decodeRGBA(desc.format, staging.mapped(), size_t(w) * h);
}

std::vector<float> decodeRGBA(VkFormat format, const void* data, size_t pixelCount) {
    FormatLayout fl = layoutOf(format);
    if (fl.channels == 0) throw Error(ExitCode::Failure, "decodeRGBA: unsupported format");
    size_t bpp = bytesPerPixel(format);
    std::vector<float> out(pixelCount * 4, 0.0f);
    const auto* bytes = static_cast<const uint8_t*>(data);
    for (size_t i = 0; i < pixelCount; ++i) {
        for (int c = 0; c < fl.channels; ++c) {
            const uint8_t* p = bytes + i * bpp;
            float v;
            if (fl.kind == FormatLayout::Unorm8) {
                v = p[c] / 255.0f;
            } else if (fl.kind == FormatLayout::Half) {
                uint16_t hv;
                std::memcpy(&hv, p + 2 * c, 2);
                v = halfToFloat(hv);
            } else {
                std::memcpy(&v, p + 4 * c, 4);
            }
            out[i * 4 + c] = v;
        }
        if (fl.channels < 4) out[i * 4 + 3] = 1.0f;
    }
    return out;
}

}  // namespace speculum::gpu
