// Internal state of a FrameGraph, shared by the builder, the compile stages and the dumps.
#pragma once

#include <speculum/framegraph.hpp>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

namespace speculum {

// One texture use declared by a pass; `version` is the version of the handle it was given.
struct TextureAccess {
    uint32_t texture = 0;
    uint32_t version = 0;
    TextureUsage usage = TextureUsage::Sampled;
    Subresource range;  // resolved against the texture's mips and layers
    bool write = false;
};

struct BufferAccess {
    uint32_t buffer = 0;
    uint32_t version = 0;
    BufferUsage usage = BufferUsage::StorageRead;
    bool write = false;
};

struct PassNode {
    std::string name;
    PassType type = PassType::Raster;
    std::function<void(PassContext&)> execute;
    bool sideEffect = false;
    std::vector<TextureAccess> textures;  // in declaration order
    std::vector<BufferAccess> buffers;
};

struct TextureNode {
    TextureInfo info;
    std::optional<ImportedTexture> imported;
    uint32_t version = 0;           // current (latest) version
    std::vector<uint32_t> writers;  // writers[v - 1] is the pass that produced version v
    bool output = false;
};

struct BufferNode {
    std::string name;
    BufferDesc desc;
    std::optional<ImportedBuffer> imported;
    uint32_t version = 0;
    std::vector<uint32_t> writers;
    bool output = false;
    VkBufferUsageFlags usage = 0;  // union over surviving passes, set by compile()
};

struct FrameGraph::Impl {
    FrameGraphConfig config;
    std::vector<PassNode> passes;
    std::vector<TextureNode> textures;
    std::vector<BufferNode> buffers;

    // Histories imported this frame and the texture id of their `current` image.
    std::vector<std::pair<History*, uint32_t>> histories;

    CompiledGraph compiled;
    bool isCompiled = false;
    uint64_t generation = 0;  // bumped by every compile(), so execute() knows when to realize
    const FrameGraphExecutor* realizedBy = nullptr;
    uint64_t realizedGeneration = 0;
};

// Names the resource of an access, for error messages and dumps.
inline const std::string& textureName(const FrameGraph::Impl& g, uint32_t id) {
    return g.textures[id].info.name;
}

// Extent of one mip of a resolved texture: never below 1.
inline uint32_t mipExtent(uint32_t size, uint32_t mip) {
    return mip >= 32 ? 1u : std::max(1u, size >> mip);
}

const char* usageName(TextureUsage usage);
const char* usageName(BufferUsage usage);
const char* layoutName(VkImageLayout layout);

}  // namespace speculum

namespace speculum {


}  // namespace speculum
