// The frame graph: declare passes and resources, compile (pure CPU), execute (Vulkan).
// After Frostbite's FrameGraph as Filament and Granite implement it. See docs/design.md section 3 (the frame graph).
//
//   FrameGraph fg({1280, 720});
//   struct GBuf { TextureHandle albedo; TextureHandle depth; };
//   auto& g = fg.addPass<GBuf>("render.gbuffer", PassType::Raster,
//       [&](PassBuilder& b, GBuf& d) {
//           d.albedo = b.write(b.create("render.albedo", {.format = VK_FORMAT_R8G8B8A8_UNORM}),
//                              TextureUsage::ColorAttachment);
//       },
//       [=](const GBuf& d, PassContext& ctx) { /* record into ctx.cmd() */ });
//   fg.markOutput(g.albedo);
//   fg.compile(allocator);
//   fg.execute(executor, cmd);
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace speculum {

inline constexpr uint32_t kAllMips = std::numeric_limits<uint32_t>::max();
inline constexpr uint32_t kAllLayers = std::numeric_limits<uint32_t>::max();

struct TextureTag {};
struct BufferTag {};

// A typed, versioned handle. Writing a resource returns a new version; any use of an older
// version afterwards is a stale-handle error (reported by the builder, with names).
template <class Tag>
struct Handle {
    uint32_t id = std::numeric_limits<uint32_t>::max();
    uint32_t version = 0;
    bool valid() const { return id != std::numeric_limits<uint32_t>::max(); }
    friend bool operator==(const Handle&, const Handle&) = default;
};
using TextureHandle = Handle<TextureTag>;
using BufferHandle = Handle<BufferTag>;

struct TextureDesc {
    // Absolute size when width/height > 0; otherwise ceil(size * relativeScale) of `relativeTo`
    // (a texture of the same graph: half-resolution passes follow their full-resolution input)
    // or, when that is not valid, of the graph's output.
    uint32_t width = 0;
    uint32_t height = 0;
    float relativeScale = 1.0f;
    VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    uint32_t mips = 1;
    uint32_t layers = 1;  // 6 * n for cube arrays
    bool cube = false;
    // Last, so that positional initializers of the fields above keep their meaning (a format
    // there would otherwise become this handle's id by brace elision).
    TextureHandle relativeTo;
};

struct BufferDesc {
    VkDeviceSize size = 0;
};

struct Subresource {
    uint32_t baseMip = 0;
    uint32_t mipCount = kAllMips;
    uint32_t baseLayer = 0;
    uint32_t layerCount = kAllLayers;
    friend bool operator==(const Subresource&, const Subresource&) = default;
};
inline Subresource mipLevel(uint32_t mip) { return {mip, 1, 0, kAllLayers}; }

enum class PassType : uint8_t { Raster, Compute, Transfer };

// How a pass touches a texture; with the pass type this fixes stage, access and layout.
enum class TextureUsage : uint8_t {
    ColorAttachment,       // write, COLOR_ATTACHMENT_OPTIMAL
    DepthAttachment,       // write, DEPTH_ATTACHMENT_OPTIMAL (depth test + write)
    DepthRead,             // read as depth attachment (test only), DEPTH_READ_ONLY_OPTIMAL
    Sampled,               // read in shaders, SHADER_READ_ONLY_OPTIMAL
    StorageRead,           // imageLoad, GENERAL
    StorageWrite,          // imageStore, GENERAL
    TransferSrc,           // TRANSFER_SRC_OPTIMAL
    TransferDst,           // TRANSFER_DST_OPTIMAL
    Present,               // PRESENT_SRC_KHR (final use of a swapchain image)
};

enum class BufferUsage : uint8_t { Uniform, StorageRead, StorageWrite, TransferSrc, TransferDst, Vertex, Index, Indirect };

// Resolved size and format of a texture, for execute() and tests.
struct TextureInfo {
    std::string name;
    TextureDesc desc;       // with width/height resolved
    VkImageUsageFlags usage = 0;  // union of all usages in the graph
    bool imported = false;
};

// An image owned outside the graph (swapchain image, history buffer, probe cubemap).
struct ImportedTexture {
    VkImage image = VK_NULL_HANDLE;
    VkImageLayout initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;  // layout it is in when the frame starts
    VkImageLayout finalLayout = VK_IMAGE_LAYOUT_UNDEFINED;    // UNDEFINED: leave in the last used layout
    VkImageUsageFlags usage = 0;
};
struct ImportedBuffer {
    VkBuffer buffer = VK_NULL_HANDLE;
};

class FrameGraph;
class PassContext;

// History that lives across frames (docs/design.md section 3, frame graph): two images of one description that the
// graph swaps each frame. FrameGraph::importHistory() gives this frame's `previous` (what the last
// executed frame wrote) and the `current` image to write; execute() commits it: when a pass that
// survived culling wrote `current`, it becomes the next frame's previous and the history is valid;
// when none did, the history is not valid. Both images stay in SHADER_READ_ONLY_OPTIMAL between
// frames (their owner puts them there once, gpu::HistoryImages does).
class History {
public:
    History() = default;
    History(const TextureDesc& desc, VkImage first, VkImage second, VkImageUsageFlags usage)
        : desc_(desc), images_{first, second}, usage_(usage) {}
    // The previous image holds the last executed frame's write.
    bool valid() const { return valid_; }
    // Camera cuts, scene changes, frames the owner skipped: the next previous is not valid.
    void invalidate() { valid_ = false; }
    VkImage previousImage() const { return images_[1 - current_]; }
    VkImage currentImage() const { return images_[current_]; }

private:
    friend class FrameGraph;
    TextureDesc desc_;
    VkImage images_[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};
    VkImageUsageFlags usage_ = 0;
    uint32_t current_ = 0;
    bool valid_ = false;
};

struct HistoryHandles {
    TextureHandle previous;  // read it; its content means something only when `valid`
    TextureHandle current;   // write it this frame (all of it: its old content is discarded)
    bool valid = false;      // History::valid() when imported
};

// Given to a pass's setup function: declares what the pass creates, reads and writes.
class PassBuilder {
public:
    TextureHandle create(const std::string& name, const TextureDesc& desc);
    BufferHandle create(const std::string& name, const BufferDesc& desc);
    // Reads return the same handle; writes return the next version of it.
    TextureHandle read(TextureHandle h, TextureUsage usage, Subresource range = {});
    TextureHandle write(TextureHandle h, TextureUsage usage, Subresource range = {});
    BufferHandle read(BufferHandle h, BufferUsage usage);
    BufferHandle write(BufferHandle h, BufferUsage usage);
    // The pass has effects outside the graph (readback, present): never culled.
    void sideEffect();

private:
    friend class FrameGraph;
    PassBuilder(FrameGraph& graph, uint32_t pass) : graph_(graph), pass_(pass) {}
    FrameGraph& graph_;
    uint32_t pass_;
};

// ---- compile() results: plain data, compared exactly by the unit tests ------------------------

struct TextureBarrier {
    uint32_t texture = 0;  // resource id
    Subresource range;     // resolved: never kAllMips / kAllLayers
    VkPipelineStageFlags2 srcStage = 0;
    VkAccessFlags2 srcAccess = 0;
    VkPipelineStageFlags2 dstStage = 0;
    VkAccessFlags2 dstAccess = 0;
    VkImageLayout oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImageLayout newLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    friend bool operator==(const TextureBarrier&, const TextureBarrier&) = default;
};
struct BufferBarrier {
    uint32_t buffer = 0;
    VkPipelineStageFlags2 srcStage = 0;
    VkAccessFlags2 srcAccess = 0;
    VkPipelineStageFlags2 dstStage = 0;
    VkAccessFlags2 dstAccess = 0;
    friend bool operator==(const BufferBarrier&, const BufferBarrier&) = default;
};

struct CompiledPass {
    uint32_t pass = 0;  // index into the declared passes
    std::vector<TextureBarrier> textureBarriers;  // recorded before the pass
    std::vector<BufferBarrier> bufferBarriers;
};

// First and last position (in execution order) at which a transient resource is used.
struct Lifetime {
    uint32_t first = 0;
    uint32_t last = 0;
};

struct MemoryRequirements {
    VkDeviceSize size = 0;
    VkDeviceSize alignment = 1;
    uint32_t memoryTypeBits = ~0u;
};

// Placement of a transient resource in the shared transient heap.
struct Placement {
    bool isTexture = true;
    uint32_t resource = 0;
    VkDeviceSize offset = 0;
    VkDeviceSize size = 0;
};

struct MemoryStats {
    VkDeviceSize transientWithAliasing = 0;
    VkDeviceSize transientWithoutAliasing = 0;
};

struct CompiledGraph {
    std::vector<CompiledPass> passes;              // in execution order, culled passes removed
    std::vector<bool> passCulled;                  // per declared pass
    std::vector<Lifetime> textureLifetimes;        // per texture id (transients only meaningful)
    std::vector<Lifetime> bufferLifetimes;
    std::vector<Placement> placements;             // transients that survived culling
    std::vector<TextureBarrier> finalTextureBarriers;  // imported textures to their final layout
    MemoryStats memory;
};

// compile() talks to the device only through this, so tests can use a fake.
class ResourceAllocator {
public:
    virtual ~ResourceAllocator() = default;
    virtual MemoryRequirements requirements(const TextureInfo& texture) const = 0;
    virtual MemoryRequirements requirements(const BufferDesc& buffer, VkBufferUsageFlags usage) const = 0;
};

// Turns a compiled graph into Vulkan objects and records it; implemented in engine/gpu.
class FrameGraphExecutor {
public:
    virtual ~FrameGraphExecutor() = default;
    // Called once per compile: create/alias transient images and buffers.
    virtual void realize(const FrameGraph& graph, const CompiledGraph& compiled) = 0;
    virtual VkImage image(uint32_t texture) const = 0;
    virtual VkImageView view(uint32_t texture, Subresource range, VkImageViewType type) = 0;
    virtual VkBuffer buffer(uint32_t buffer) const = 0;
    // passIndex: position in execution order (0 starts a frame's recording).
    virtual void beginPass(VkCommandBuffer cmd, const std::string& name, uint32_t passIndex) = 0;
    virtual void endPass(VkCommandBuffer cmd, uint32_t passIndex) = 0;
};

// Given to a pass's execute function.
class PassContext {
public:
    VkCommandBuffer cmd() const { return cmd_; }
    VkImage image(TextureHandle h) const;
    // 2D view (or cube / array view when the texture is one) of the given subresource range.
    VkImageView view(TextureHandle h, Subresource range = {}) const;
    VkImageView view(TextureHandle h, Subresource range, VkImageViewType type) const;
    VkBuffer buffer(BufferHandle h) const;
    const TextureInfo& info(TextureHandle h) const;
    VkExtent2D extent(TextureHandle h, uint32_t mip = 0) const;

private:
    friend class FrameGraph;
    PassContext(const FrameGraph& g, FrameGraphExecutor& e, VkCommandBuffer c) : graph_(g), exec_(e), cmd_(c) {}
    const FrameGraph& graph_;
    FrameGraphExecutor& exec_;
    VkCommandBuffer cmd_;
};

// Thrown for user errors in the graph; the message names the pass and the resource.
class FrameGraphError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct FrameGraphConfig {
    uint32_t outputWidth = 1;
    uint32_t outputHeight = 1;
    bool aliasing = true;
};

class FrameGraph {
public:
    explicit FrameGraph(FrameGraphConfig config);
    ~FrameGraph();
    FrameGraph(const FrameGraph&) = delete;
    FrameGraph& operator=(const FrameGraph&) = delete;

    template <class Data, class Setup, class Execute>
    const Data& addPass(const std::string& name, PassType type, Setup&& setup, Execute&& execute) {
        auto data = std::make_shared<Data>();
        uint32_t index = beginPass(name, type);
        PassBuilder builder(*this, index);
        setup(builder, *data);
        setExecute(index, [data, exec = std::forward<Execute>(execute)](PassContext& ctx) { exec(*data, ctx); });
        return *data;
    }

    TextureHandle importTexture(const std::string& name, const TextureDesc& desc, const ImportedTexture& texture);
    BufferHandle importBuffer(const std::string& name, const BufferDesc& desc, const ImportedBuffer& buffer);
    // Imports both images of a history (NAME.previous, NAME.current); execute() swaps and
    // validates it. The History must outlive execute().
    HistoryHandles importHistory(const std::string& name, History& history);
    // Keeps the producers of this resource alive through culling.
    void markOutput(TextureHandle h);
    void markOutput(BufferHandle h);

    // Pure CPU. Throws FrameGraphError for user errors.
    const CompiledGraph& compile(const ResourceAllocator& allocator);
    // Records every surviving pass in order into cmd, each with its barriers, label and timestamps,
    // then commits the imported histories.
    void execute(FrameGraphExecutor& executor, VkCommandBuffer cmd);
    // Swaps every history imported this frame whose current image a surviving pass writes, and
    // marks the others not valid. execute() calls it; public for hosts that record the compiled
    // passes themselves and for the unit tests (no GPU).
    void commitHistories();

    const CompiledGraph& compiled() const;
    const FrameGraphConfig& config() const;
    uint32_t passCount() const;
    const std::string& passName(uint32_t pass) const;
    PassType passType(uint32_t pass) const;
    uint32_t textureCount() const;
    const TextureInfo& texture(uint32_t id) const;
    const ImportedTexture* importedTexture(uint32_t id) const;  // null for transients
    uint32_t bufferCount() const;
    const std::string& bufferName(uint32_t id) const;
    const BufferDesc& bufferDesc(uint32_t id) const;
    // Union of bufferUsageOf over the passes that survived the last compile().
    VkBufferUsageFlags bufferUsage(uint32_t id) const;
    const ImportedBuffer* importedBuffer(uint32_t id) const;

    // Graphviz DOT and JSON: passes, resources, barriers, memory (and timings when given).
    std::string dumpDot() const;
    nlohmann::json dumpJson() const;

    struct Impl;

private:
    friend class PassBuilder;
    friend class PassContext;
    uint32_t beginPass(const std::string& name, PassType type);
    void setExecute(uint32_t pass, std::function<void(PassContext&)> fn);
    std::unique_ptr<Impl> impl_;
};

// Stage/access/layout that a usage implies in a pass of the given type (used by compile's
// barrier stage and by tests that spell out expected barriers).
struct AccessInfo {
    VkPipelineStageFlags2 stage = 0;
    VkAccessFlags2 access = 0;
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    bool writes = false;
};
AccessInfo accessOf(TextureUsage usage, PassType type);
AccessInfo accessOf(BufferUsage usage, PassType type);
VkImageUsageFlags imageUsageOf(TextureUsage usage);
// The aspect barriers and views use: depth alone for depth/stencil formats (the graph tracks
// depth layouts, which apply to one aspect), stencil for S8, colour otherwise.
VkImageAspectFlags aspectOf(VkFormat format);
VkBufferUsageFlags bufferUsageOf(BufferUsage usage);

}  // namespace speculum
