#include "speculum/app/device_budget.hpp"

#include "speculum/core.hpp"
#include "speculum/limits.hpp"

#include <algorithm>
#include <cstdlib>

namespace speculum::app {
namespace {

uint64_t largestDeviceLocalHeap(const gpu::Context& ctx) {
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(ctx.physicalDevice(), &mem);
    uint64_t best = 0;
    for (uint32_t i = 0; i < mem.memoryHeapCount; ++i)
        if (mem.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) best = std::max(best, mem.memoryHeaps[i].size);
    return best;
}

uint64_t maxAllocation(const gpu::Context& ctx) {
    VkPhysicalDeviceMaintenance3Properties m3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    p2.pNext = &m3;
    vkGetPhysicalDeviceProperties2(ctx.physicalDevice(), &p2);
    return m3.maxMemoryAllocationSize;
}

}  // namespace

void checkSceneFitsDevice(const gpu::Context& ctx, const Scene& scene) {
    const std::string file = scene.path.string();
    const std::string device = " (" + ctx.deviceName() + ")";
    SceneBytes b = sceneBytes(scene);
    uint64_t heap = largestDeviceLocalHeap(ctx);
    uint64_t budget = uint64_t(double(heap) * limits::kSceneHeapShare);
    std::string share = "half of the " + limits::bytesText(heap) + " device-local heap";
    // A smaller budget on request: tests stand in for a small GPU with it, and a user sharing the
    // device with other programs can keep the scene in its corner.
    if (const char* mb = std::getenv("SPECULUM_SCENE_BUDGET_MB"); mb && *mb) {
        char* end = nullptr;
        unsigned long long v = std::strtoull(mb, &end, 10);
        if (*end || v == 0)
            throw argumentError("SPECULUM_SCENE_BUDGET_MB needs a whole number of MiB, got '" + std::string(mb) + "'");
        if ((v << 20) < budget) {
            budget = v << 20;
            share = "SPECULUM_SCENE_BUDGET_MB";
        }
    }
    if (b.total() > budget)
        throw inputError(file, "the scene needs " + limits::bytesText(b.total()) + " of device memory (vertices " +
                                   limits::bytesText(b.vertices) + ", indices " + limits::bytesText(b.indices) +
                                   ", textures " + limits::bytesText(b.textures) + "), more than the " +
                                   limits::bytesText(budget) + " it may use (" + share + ")" + device);
    // The renderer puts all vertices in one buffer and all indices in another.
    uint64_t single = maxAllocation(ctx);
    for (auto [what, bytes] : {std::pair{"vertex", b.vertices}, std::pair{"index", b.indices}})
        if (bytes > single)
            throw inputError(file, std::string("the scene's ") + what + " buffer would be " + limits::bytesText(bytes) +
                                       ", more than the device allows in one allocation (" + limits::bytesText(single) +
                                       ")" + device);
    uint32_t maxDim = ctx.properties().limits.maxImageDimension2D;
    for (const Image& img : scene.images)
        if (img.width > maxDim || img.height > maxDim)
            throw inputError(file, "image '" + img.name + "' is " + std::to_string(img.width) + "x" +
                                       std::to_string(img.height) + ", larger than the device's " +
                                       std::to_string(maxDim) + " pixels a side" + device);
}

}  // namespace speculum::app
