// Vulkan side of the frame graph: transient sizing, realization (one aliased heap) and
// per-pass labels and timestamps.
#include <speculum/gpu/fg_executor.hpp>

#include <algorithm>
#include <deque>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace speculum::gpu {
namespace {

// Move-only owner of one device-level Vulkan object.
template <class T, void (*Destroy)(VkDevice, T, const VkAllocationCallbacks*)>
class Owned {
public:
    Owned() = default;
    Owned(VkDevice device, T handle) : device_(device), handle_(handle) {}
    Owned(Owned&& o) noexcept : device_(o.device_), handle_(std::exchange(o.handle_, T{})) {}
    Owned& operator=(Owned&& o) noexcept {
        if (this != &o) {
            reset();
            device_ = o.device_;
            handle_ = std::exchange(o.handle_, T{});
        }
        return *this;
    }
    ~Owned() { reset(); }
    T get() const { return handle_; }

private:
    void reset() {
        if (handle_ != T{}) Destroy(device_, std::exchange(handle_, T{}), nullptr);
    }
    VkDevice device_ = VK_NULL_HANDLE;
    T handle_{};
};

using OwnedImage = Owned<VkImage, vkDestroyImage>;
using OwnedBuffer = Owned<VkBuffer, vkDestroyBuffer>;
using OwnedView = Owned<VkImageView, vkDestroyImageView>;
using OwnedMemory = Owned<VkDeviceMemory, vkFreeMemory>;
using OwnedQueryPool = Owned<VkQueryPool, vkDestroyQueryPool>;

void check(VkResult result, const char* what, const std::string& name) {
    if (result != VK_SUCCESS) {
        throw std::runtime_error(std::string("frame graph executor: ") + what + " failed (" +
                                 std::to_string(int(result)) + ") for '" + name + "'");
    }
}

VkImageCreateInfo imageCreateInfo(const TextureInfo& t) {
    VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ci.flags = t.desc.cube ? VkImageCreateFlags(VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT) : 0;
    ci.imageType = VK_IMAGE_TYPE_2D;
    ci.format = t.desc.format;
    ci.extent = {t.desc.width, t.desc.height, 1};
    ci.mipLevels = t.desc.mips;
    ci.arrayLayers = t.desc.layers;
    ci.samples = VK_SAMPLE_COUNT_1_BIT;
    ci.tiling = VK_IMAGE_TILING_OPTIMAL;
    // A transient nobody reads or writes through a usage flag still needs a valid one.
    ci.usage = t.usage ? t.usage : VkImageUsageFlags(VK_IMAGE_USAGE_TRANSFER_DST_BIT);
    ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    return ci;
}

VkBufferCreateInfo bufferCreateInfo(const BufferDesc& desc, VkBufferUsageFlags usage) {
    VkBufferCreateInfo ci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    ci.size = desc.size;
    ci.usage = usage ? usage : VkBufferUsageFlags(VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    ci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    return ci;
}

// Everything that decides the objects realize() creates; equal keys mean reusable objects.
using LayoutKey = std::vector<uint64_t>;

LayoutKey layoutKey(const FrameGraph& graph, const CompiledGraph& compiled) {
    LayoutKey key;
    for (const Placement& p : compiled.placements) {
        key.insert(key.end(), {p.isTexture, p.resource, p.offset, p.size});
        if (p.isTexture) {
            const TextureInfo& t = graph.texture(p.resource);
            key.insert(key.end(), {uint64_t(t.desc.format), t.desc.width, t.desc.height,
                                   t.desc.mips, t.desc.layers, t.desc.cube, t.usage});
        } else {
            key.insert(key.end(), {graph.bufferDesc(p.resource).size,
                                   graph.bufferUsage(p.resource)});
        }
    }
    return key;
}

// The image's size and format are part of the key: a host that destroys an imported image and
// imports a new one of another size may get the same handle value back (lavapipe's handles are
// heap addresses), and a view of the old one then writes past the new one's memory (issue 16:
// the game's dynamic resolution resizing the reflections module's history).
using ViewKey = std::tuple<VkImage, uint32_t, uint32_t, uint32_t, uint32_t, VkImageViewType, uint32_t, uint32_t,
                           uint32_t, VkFormat>;

}  // namespace

// The objects of one realized layout. Members are destroyed bottom-up: views, then images and
// buffers, then the memory they were bound to.
struct Realized {
    LayoutKey key;
    std::vector<OwnedMemory> memory;
    VkDeviceSize heapSize = 0;
    std::vector<OwnedImage> ownedImages;
    std::vector<OwnedBuffer> ownedBuffers;
    std::map<ViewKey, OwnedView> views;
};

struct VulkanFrameGraphExecutor::State {
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    double timestampPeriodNs = 1.0;
    uint32_t maxPasses = 0;
    uint32_t framesInFlight = 0;
    PFN_vkCmdBeginDebugUtilsLabelEXT beginLabel = nullptr;
    PFN_vkCmdEndDebugUtilsLabelEXT endLabel = nullptr;
    VkPhysicalDeviceMemoryProperties memoryProperties{};
    OwnedQueryPool queries;

    std::unique_ptr<Realized> realized;
    std::deque<std::pair<uint64_t, std::unique_ptr<Realized>>> retired;  // (frame retired, set)
    std::map<ViewKey, OwnedView> importedViews;
    std::vector<TextureInfo> textures;  // of the graph last realized
    std::vector<VkImage> images;        // per texture id, imported ones included
    std::vector<VkBuffer> buffers;
    uint32_t passCount = 0;
    uint64_t frame = 0;
    std::vector<std::string> recordedNames;  // passes timed in the most recent frame

    uint32_t memoryType(uint32_t bits) const;
    void createObjects(const FrameGraph& graph, const CompiledGraph& compiled, Realized& r);
    void bindMemory(const FrameGraph& graph, const CompiledGraph& compiled, Realized& r);
};

// ---- VulkanResourceAllocator --------------------------------------------------------------

VulkanResourceAllocator::VulkanResourceAllocator(VkPhysicalDevice physicalDevice,
                                                 VkDevice device)
    : device_(device) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(physicalDevice, &props);
    granularity_ = std::max<VkDeviceSize>(1, props.limits.bufferImageGranularity);
}

MemoryRequirements VulkanResourceAllocator::requirements(const TextureInfo& texture) const {
    VkImageCreateInfo ci = imageCreateInfo(texture);
    VkDeviceImageMemoryRequirements query{VK_STRUCTURE_TYPE_DEVICE_IMAGE_MEMORY_REQUIREMENTS};
    query.pCreateInfo = &ci;
    VkMemoryRequirements2 req{VK_STRUCTURE_TYPE_MEMORY_REQUIREMENTS_2};
    vkGetDeviceImageMemoryRequirements(device_, &query, &req);
    const VkMemoryRequirements& m = req.memoryRequirements;
    return {m.size, std::max(m.alignment, granularity_), m.memoryTypeBits};
}

MemoryRequirements VulkanResourceAllocator::requirements(const BufferDesc& buffer,
                                                         VkBufferUsageFlags usage) const {
    VkBufferCreateInfo ci = bufferCreateInfo(buffer, usage);
    VkDeviceBufferMemoryRequirements query{VK_STRUCTURE_TYPE_DEVICE_BUFFER_MEMORY_REQUIREMENTS};
    query.pCreateInfo = &ci;
    VkMemoryRequirements2 req{VK_STRUCTURE_TYPE_MEMORY_REQUIREMENTS_2};
    vkGetDeviceBufferMemoryRequirements(device_, &query, &req);
    const VkMemoryRequirements& m = req.memoryRequirements;
    return {m.size, std::max(m.alignment, granularity_), m.memoryTypeBits};
}

// ---- VulkanFrameGraphExecutor: construction and realization -----------------------------

VulkanFrameGraphExecutor::VulkanFrameGraphExecutor(VkInstance instance,
                                                   VkPhysicalDevice physicalDevice,
                                                   VkDevice device, double timestampPeriodNs,
                                                   uint32_t maxPasses, uint32_t framesInFlight)
    : state_(std::make_unique<State>()) {
    State& s = *state_;
    s.physicalDevice = physicalDevice;
    s.device = device;
    s.timestampPeriodNs = timestampPeriodNs;
    s.maxPasses = std::max(1u, maxPasses);
    s.framesInFlight = std::max(1u, framesInFlight);
    // Null unless VK_EXT_debug_utils is enabled on the instance; labels are then skipped.
    s.beginLabel = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(instance, "vkCmdBeginDebugUtilsLabelEXT"));
    s.endLabel = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(instance, "vkCmdEndDebugUtilsLabelEXT"));
    vkGetPhysicalDeviceMemoryProperties(physicalDevice, &s.memoryProperties);

    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = 2 * s.maxPasses;
    VkQueryPool pool = VK_NULL_HANDLE;
    check(vkCreateQueryPool(device, &qi, nullptr, &pool), "vkCreateQueryPool", "timestamps");
    s.queries = OwnedQueryPool(device, pool);
}

VulkanFrameGraphExecutor::~VulkanFrameGraphExecutor() = default;

uint32_t VulkanFrameGraphExecutor::State::memoryType(uint32_t bits) const {
    for (VkMemoryPropertyFlags wanted : {VkMemoryPropertyFlags(VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT),
                                         VkMemoryPropertyFlags(0)}) {
        for (uint32_t i = 0; i < memoryProperties.memoryTypeCount; ++i) {
            if ((bits & (1u << i)) &&
                (memoryProperties.memoryTypes[i].propertyFlags & wanted) == wanted) {
                return i;
            }
        }
    }
    return UINT32_MAX;
}

void VulkanFrameGraphExecutor::State::createObjects(const FrameGraph& graph,
                                                    const CompiledGraph& compiled, Realized& r) {
    for (const Placement& p : compiled.placements) {
        if (p.isTexture) {
            VkImageCreateInfo ci = imageCreateInfo(graph.texture(p.resource));
            VkImage image = VK_NULL_HANDLE;
            check(vkCreateImage(device, &ci, nullptr, &image), "vkCreateImage",
                  graph.texture(p.resource).name);
            r.ownedImages.emplace_back(device, image);
            images[p.resource] = image;
        } else {
            VkBufferCreateInfo ci =
                bufferCreateInfo(graph.bufferDesc(p.resource), graph.bufferUsage(p.resource));
            VkBuffer buffer = VK_NULL_HANDLE;
            check(vkCreateBuffer(device, &ci, nullptr, &buffer), "vkCreateBuffer",
                  graph.bufferName(p.resource));
            r.ownedBuffers.emplace_back(device, buffer);
            buffers[p.resource] = buffer;
        }
    }
}

// One heap for the aliased layout when every resource fits its placement and one memory type
// suits all of them; otherwise a dedicated allocation each.
void VulkanFrameGraphExecutor::State::bindMemory(const FrameGraph& graph,
                                                 const CompiledGraph& compiled, Realized& r) {
    std::vector<VkMemoryRequirements> reqs;
    uint32_t commonBits = ~0u;
    bool fits = true;
    for (const Placement& p : compiled.placements) {
        VkMemoryRequirements m;
        if (p.isTexture) vkGetImageMemoryRequirements(device, images[p.resource], &m);
        else vkGetBufferMemoryRequirements(device, buffers[p.resource], &m);
        commonBits &= m.memoryTypeBits;
        fits = fits && m.size <= p.size && p.offset % std::max<VkDeviceSize>(1, m.alignment) == 0;
        r.heapSize = std::max(r.heapSize, p.offset + m.size);
        reqs.push_back(m);
    }
    const uint32_t heapType = memoryType(commonBits);
    const bool shared = fits && heapType != UINT32_MAX && !compiled.placements.empty();
    auto allocate = [&](VkDeviceSize size, uint32_t type, const std::string& name) {
        VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        ai.allocationSize = size;
        ai.memoryTypeIndex = type;
        VkDeviceMemory memory = VK_NULL_HANDLE;
        check(vkAllocateMemory(device, &ai, nullptr, &memory), "vkAllocateMemory", name);
        r.memory.emplace_back(device, memory);
        return memory;
    };
    if (shared) allocate(r.heapSize, heapType, "transient heap");
    else r.heapSize = 0;
    for (size_t i = 0; i < compiled.placements.size(); ++i) {
        const Placement& p = compiled.placements[i];
        const std::string& name =
            p.isTexture ? graph.texture(p.resource).name : graph.bufferName(p.resource);
        VkDeviceMemory memory = VK_NULL_HANDLE;
        VkDeviceSize offset = 0;
        if (shared) {
            memory = r.memory.front().get();
            offset = p.offset;
        } else {
            uint32_t type = memoryType(reqs[i].memoryTypeBits);
            if (type == UINT32_MAX) check(VK_ERROR_FEATURE_NOT_PRESENT, "memory type", name);
            memory = allocate(reqs[i].size, type, name);
        }
        if (p.isTexture) {
            check(vkBindImageMemory(device, images[p.resource], memory, offset),
                  "vkBindImageMemory", name);
        } else {
            check(vkBindBufferMemory(device, buffers[p.resource], memory, offset),
                  "vkBindBufferMemory", name);
        }
    }
}

void VulkanFrameGraphExecutor::realize(const FrameGraph& graph, const CompiledGraph& compiled) {
    State& s = *state_;
    s.passCount = uint32_t(compiled.passes.size());
    s.textures.clear();
    s.images.assign(graph.textureCount(), VK_NULL_HANDLE);
    s.buffers.assign(graph.bufferCount(), VK_NULL_HANDLE);
    for (uint32_t t = 0; t < graph.textureCount(); ++t) {
        s.textures.push_back(graph.texture(t));
        if (const ImportedTexture* imported = graph.importedTexture(t)) {
            s.images[t] = imported->image;
        }
    }
    for (uint32_t b = 0; b < graph.bufferCount(); ++b) {
        if (const ImportedBuffer* imported = graph.importedBuffer(b)) {
            s.buffers[b] = imported->buffer;
        }
    }
    // Views of imports that left the graph may name destroyed images whose handle values get
    // reused (by an image of another size, or later by one of the same size again): keep only
    // views of an image imported now with the same size and format.
    std::set<std::tuple<VkImage, uint32_t, uint32_t, uint32_t, VkFormat>> imports;
    for (uint32_t t = 0; t < graph.textureCount(); ++t)
        if (graph.importedTexture(t)) {
            const TextureDesc& d = s.textures[t].desc;
            imports.insert({s.images[t], d.width, d.height, d.layers, d.format});
        }
    for (auto it = s.importedViews.begin(); it != s.importedViews.end();) {
        const ViewKey& k = it->first;
        bool live = imports.count({std::get<0>(k), std::get<6>(k), std::get<7>(k), std::get<8>(k), std::get<9>(k)}) > 0;
        it = live ? std::next(it) : s.importedViews.erase(it);
    }

    LayoutKey key = layoutKey(graph, compiled);
    if (s.realized && s.realized->key == key) {
        // Same layout: objects are reused; only their per-id lookup needs refreshing.
        size_t image = 0, buffer = 0;
        for (const Placement& p : compiled.placements) {
            if (p.isTexture) s.images[p.resource] = s.realized->ownedImages[image++].get();
            else s.buffers[p.resource] = s.realized->ownedBuffers[buffer++].get();
        }
        return;
    }
    auto fresh = std::make_unique<Realized>();
    fresh->key = std::move(key);
    s.createObjects(graph, compiled, *fresh);
    s.bindMemory(graph, compiled, *fresh);
    // Frames still in flight may use the old objects.
    if (s.realized) s.retired.emplace_back(s.frame, std::move(s.realized));
    s.realized = std::move(fresh);
}

// ---- VulkanFrameGraphExecutor: lookups and recording ------------------------------------

VkImage VulkanFrameGraphExecutor::image(uint32_t texture) const {
    return state_->images.at(texture);
}

VkBuffer VulkanFrameGraphExecutor::buffer(uint32_t buffer) const {
    return state_->buffers.at(buffer);
}

VkImageView VulkanFrameGraphExecutor::view(uint32_t texture, Subresource range,
                                           VkImageViewType type) {
    State& s = *state_;
    const TextureInfo& info = s.textures.at(texture);
    VkImage image = s.images.at(texture);
    if (image == VK_NULL_HANDLE) {
        throw std::logic_error("frame graph executor: '" + info.name + "' has no image");
    }
    if (range.mipCount == kAllMips) range.mipCount = info.desc.mips - range.baseMip;
    if (range.layerCount == kAllLayers) range.layerCount = info.desc.layers - range.baseLayer;
    ViewKey key{image,           range.baseMip,    range.mipCount,   range.baseLayer, range.layerCount,
                type,            info.desc.width, info.desc.height, info.desc.layers, info.desc.format};
    auto& cache = info.imported ? s.importedViews : s.realized->views;
    if (auto it = cache.find(key); it != cache.end()) return it->second.get();

    VkImageViewCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    ci.image = image;
    ci.viewType = type;
    ci.format = info.desc.format;
    ci.subresourceRange = {aspectOf(info.desc.format), range.baseMip, range.mipCount,
                           range.baseLayer, range.layerCount};
    VkImageView view = VK_NULL_HANDLE;
    check(vkCreateImageView(s.device, &ci, nullptr, &view), "vkCreateImageView", info.name);
    cache.emplace(key, OwnedView(s.device, view));
    return view;
}

void VulkanFrameGraphExecutor::beginPass(VkCommandBuffer cmd, const std::string& name,
                                         uint32_t passIndex) {
    State& s = *state_;
    if (passIndex == 0) {
        ++s.frame;
        while (!s.retired.empty() && s.frame - s.retired.front().first > s.framesInFlight) {
            s.retired.pop_front();
        }
        uint32_t timed = std::min(std::max(s.passCount, 1u), s.maxPasses);
        vkCmdResetQueryPool(cmd, s.queries.get(), 0, 2 * timed);
        s.recordedNames.clear();
    }
    if (s.beginLabel) {
        VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
        label.pLabelName = name.c_str();
        s.beginLabel(cmd, &label);
    }
    if (passIndex < s.maxPasses) {
        // ALL_COMMANDS on both ends: a pass's time excludes work still running from before it.
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, s.queries.get(),
                             2 * passIndex);
        if (s.recordedNames.size() <= passIndex) s.recordedNames.resize(passIndex + 1);
        s.recordedNames[passIndex] = name;
    }
}

void VulkanFrameGraphExecutor::endPass(VkCommandBuffer cmd, uint32_t passIndex) {
    State& s = *state_;
    if (passIndex < s.maxPasses) {
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, s.queries.get(),
                             2 * passIndex + 1);
    }
    if (s.endLabel) s.endLabel(cmd);
}

std::vector<PassTiming> VulkanFrameGraphExecutor::readTimings() {
    State& s = *state_;
    const uint32_t count = uint32_t(s.recordedNames.size());
    if (count == 0) return {};
    std::vector<uint64_t> ticks(2 * size_t(count));
    VkResult result = vkGetQueryPoolResults(
        s.device, s.queries.get(), 0, 2 * count, ticks.size() * sizeof(uint64_t), ticks.data(),
        sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT);
    check(result, "vkGetQueryPoolResults", "timestamps");
    std::vector<PassTiming> out;
    out.reserve(count);
    for (uint32_t i = 0; i < count; ++i) {
        uint64_t begin = ticks[2 * i], end = ticks[2 * i + 1];
        double ns = end >= begin ? double(end - begin) * s.timestampPeriodNs : 0.0;
        out.push_back({s.recordedNames[i], ns / 1e6});
    }
    return out;
}

VkDeviceSize VulkanFrameGraphExecutor::heapSize() const {
    return state_->realized ? state_->realized->heapSize : 0;
}

uint32_t VulkanFrameGraphExecutor::allocationCount() const {
    return state_->realized ? uint32_t(state_->realized->memory.size()) : 0;
}

}  // namespace speculum::gpu
