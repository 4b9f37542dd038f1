// Persistent GPU resources (buffers, images, samplers), staging uploads and readbacks.
// Transient per-frame resources belong to the frame graph, not here.
#pragma once

#include "speculum/framegraph.hpp"
#include "speculum/gpu/context.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace speculum::gpu {

// Bytes of device memory held by live Buffers and Images (persistent resources; the frame
// graph's transient heap is reported separately).
uint64_t persistentBytes();

// Adds its size to persistentBytes() for as long as it lives.
class AllocationCounter {
public:
    AllocationCounter() = default;
    explicit AllocationCounter(uint64_t bytes);
    AllocationCounter(AllocationCounter&& o) noexcept : bytes_(std::exchange(o.bytes_, 0)) {}
    AllocationCounter& operator=(AllocationCounter&& o) noexcept;
    ~AllocationCounter();

private:
    uint64_t bytes_ = 0;
};

class Buffer {
public:
    Buffer() = default;
    // hostVisible: mapped for the buffer's lifetime (uniforms, readback); otherwise device-local.
    Buffer(const Context& ctx, VkDeviceSize size, VkBufferUsageFlags usage, bool hostVisible,
           const std::string& name);
    VkBuffer get() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    void* mapped() const { return mapped_; }

private:
    Unique<VkBuffer> buffer_;
    Unique<VkDeviceMemory> memory_;
    AllocationCounter counter_;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
};

struct ImageDesc {
    uint32_t width = 1;
    uint32_t height = 1;
    VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    uint32_t mips = 1;
    uint32_t layers = 1;
    bool cube = false;
    VkImageUsageFlags usage = VK_IMAGE_USAGE_SAMPLED_BIT;
};

class Image {
public:
    Image() = default;
    Image(const Context& ctx, const ImageDesc& desc, const std::string& name);
    VkImage get() const { return image_; }
    // View of all mips and layers (cube view for cubes).
    VkImageView view() const { return view_; }
    // View of one mip (2D, or cube for cubes); created at construction for every mip.
    VkImageView mipView(uint32_t mip) const { return mipViews_.at(mip); }
    const ImageDesc& desc() const { return desc_; }
    VkImageAspectFlags aspect() const;

private:
    ImageDesc desc_;
    Unique<VkImage> image_;
    Unique<VkDeviceMemory> memory_;
    AllocationCounter counter_;
    Unique<VkImageView> view_;
    std::vector<Unique<VkImageView>> mipViews_;
};

// The two images of a frame-graph History (FrameGraph::importHistory), created cleared and in
// SHADER_READ_ONLY_OPTIMAL as the graph expects them between frames. `desc.usage` gets
// SAMPLED and TRANSFER_DST added.
class HistoryImages {
public:
    HistoryImages() = default;
    HistoryImages(const Context& ctx, ImageDesc desc, const std::string& name);
    History& history() { return history_; }
    const History& history() const { return history_; }
    const ImageDesc& desc() const { return images_[0].desc(); }

private:
    Image images_[2];
    History history_;
};

Unique<VkSampler> createSampler(const Context& ctx, VkFilter filter, VkSamplerAddressMode address,
                                bool mipmaps, VkSamplerReductionMode reduction = VK_SAMPLER_REDUCTION_MODE_WEIGHTED_AVERAGE);

// Copies data into a device-local buffer through a staging buffer.
Buffer uploadBuffer(const Context& ctx, std::span<const std::byte> data, VkBufferUsageFlags usage,
                    const std::string& name);
// Uploads mip 0 (all layers, tightly packed) and leaves the image in SHADER_READ_ONLY_OPTIMAL.
// With generateMips the remaining mips are made by linear blits.
void uploadImage(const Context& ctx, const Image& image, std::span<const std::byte> data, bool generateMips);

// Reads back one mip/layer of an image that is in `layout` (left in that layout), converted to
// float RGBA (1-, 2- and 4-channel float and unorm formats; depth D32 as R).
std::vector<float> readImageRGBA(const Context& ctx, VkImage image, const ImageDesc& desc,
                                 VkImageLayout layout, uint32_t mip = 0, uint32_t layer = 0);
size_t bytesPerPixel(VkFormat format);
// Decodes tightly packed pixels of a format readImageRGBA understands into float RGBA.
std::vector<float> decodeRGBA(VkFormat format, const void* data, size_t pixelCount);

// One image layout transition (synchronization2), coarse stages: for setup code, not frames.
void transition(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
                VkImageLayout to, uint32_t baseMip = 0, uint32_t mips = VK_REMAINING_MIP_LEVELS,
                uint32_t baseLayer = 0, uint32_t layers = VK_REMAINING_ARRAY_LAYERS);

}  // namespace speculum::gpu
