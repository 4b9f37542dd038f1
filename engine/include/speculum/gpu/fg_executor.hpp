// Vulkan implementations of the frame graph's device interfaces: sizing transients
// (VulkanResourceAllocator) and realizing + recording a compiled graph
// (VulkanFrameGraphExecutor). Both work on raw handles so they do not depend on the rest of
// the gpu layer.
//
//   gpu::VulkanResourceAllocator allocator(physicalDevice, device);
//   gpu::VulkanFrameGraphExecutor executor(instance, physicalDevice, device, timestampPeriodNs);
//   fg.compile(allocator);
//   fg.execute(executor, cmd);          // realizes on the first frame after a compile
//   ... submit, wait for the frame's fence ...
//   auto timings = executor.readTimings();
#pragma once

#include <speculum/framegraph.hpp>

#include <memory>
#include <string>
#include <vector>

namespace speculum {

struct PassTiming {
    std::string name;
    double ms = 0.0;
};

namespace gpu {

// Sizes images and buffers with vkGetDevice{Image,Buffer}MemoryRequirements (Vulkan 1.3), so
// compile() creates no object. Alignment is raised to bufferImageGranularity because buffers
// and optimal-tiling images share the one transient heap.
class VulkanResourceAllocator : public ResourceAllocator {
public:
    VulkanResourceAllocator(VkPhysicalDevice physicalDevice, VkDevice device);
    MemoryRequirements requirements(const TextureInfo& texture) const override;
    MemoryRequirements requirements(const BufferDesc& buffer,
                                    VkBufferUsageFlags usage) const override;

private:
    VkDevice device_;
    VkDeviceSize granularity_ = 1;
};

// Owns the transient heap, images, buffers, views and the timestamp query pool. realize()
// keeps everything when the placements and descriptions did not change; otherwise the old set
// is retired and destroyed framesInFlight frames later (frames are counted at passIndex 0).
class VulkanFrameGraphExecutor : public FrameGraphExecutor {
public:
    VulkanFrameGraphExecutor(VkInstance instance, VkPhysicalDevice physicalDevice,
                             VkDevice device, double timestampPeriodNs, uint32_t maxPasses = 256,
                             uint32_t framesInFlight = 3);
    ~VulkanFrameGraphExecutor() override;
    VulkanFrameGraphExecutor(const VulkanFrameGraphExecutor&) = delete;
    VulkanFrameGraphExecutor& operator=(const VulkanFrameGraphExecutor&) = delete;

    void realize(const FrameGraph& graph, const CompiledGraph& compiled) override;
    VkImage image(uint32_t texture) const override;
    VkImageView view(uint32_t texture, Subresource range, VkImageViewType type) override;
    VkBuffer buffer(uint32_t buffer) const override;
    void beginPass(VkCommandBuffer cmd, const std::string& name, uint32_t passIndex) override;
    void endPass(VkCommandBuffer cmd, uint32_t passIndex) override;

    // GPU time of each pass of the most recently recorded frame. Blocks until its queries are
    // written (VK_QUERY_RESULT_WAIT_BIT): call it only after that frame was submitted.
    std::vector<PassTiming> readTimings();

    // Bytes of the shared transient heap, 0 when resources fell back to separate allocations.
    VkDeviceSize heapSize() const;
    // Device memory allocations owned for transients (1 with a shared heap).
    uint32_t allocationCount() const;

    struct State;

private:
    std::unique_ptr<State> state_;
};

}  // namespace gpu

using gpu::VulkanFrameGraphExecutor;
using gpu::VulkanResourceAllocator;

}  // namespace speculum
