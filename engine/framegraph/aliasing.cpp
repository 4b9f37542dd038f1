// Transient memory placement. Largest first, each at the lowest aligned offset that does not
// overlap (in memory) any already placed resource whose lifetime overlaps its own: the greedy
// first-fit used by Frostbite-style graphs, good enough for the tens of resources per frame.
#include "framegraph/compile_stages.hpp"

#include <algorithm>

namespace speculum {
namespace {

struct Candidate {
    Placement placement;
    VkDeviceSize alignment = 1;
    Lifetime life;
};

VkDeviceSize alignUp(VkDeviceSize v, VkDeviceSize a) { return a <= 1 ? v : (v + a - 1) / a * a; }

bool lifetimesOverlap(const Lifetime& a, const Lifetime& b) {
    return a.first <= b.last && b.first <= a.last;
}

VkDeviceSize firstFit(const Candidate& c, const std::vector<Candidate>& placed, bool alias) {
    // Memory ranges this candidate must avoid, sorted by offset.
    std::vector<std::pair<VkDeviceSize, VkDeviceSize>> busy;
    for (const Candidate& p : placed) {
        if (!alias || lifetimesOverlap(c.life, p.life)) {
            busy.emplace_back(p.placement.offset, p.placement.offset + p.placement.size);
        }
    }
    std::sort(busy.begin(), busy.end());
    VkDeviceSize offset = 0;
    for (const auto& [begin, end] : busy) {
        if (alignUp(offset, c.alignment) + c.placement.size <= begin) break;
        offset = std::max(offset, end);
    }
    return alignUp(offset, c.alignment);
}

std::vector<Candidate> gatherTransients(const FrameGraph::Impl& g,
                                        const ResourceAllocator& allocator,
                                        const CompiledGraph& compiled) {
    std::vector<Candidate> out;
    for (uint32_t id = 0; id < g.textures.size(); ++id) {
        const Lifetime& life = compiled.textureLifetimes[id];
        if (g.textures[id].imported || !isUsed(life)) continue;
        MemoryRequirements req = allocator.requirements(g.textures[id].info);
        out.push_back({{true, id, 0, req.size}, std::max<VkDeviceSize>(1, req.alignment), life});
    }
    for (uint32_t id = 0; id < g.buffers.size(); ++id) {
        const Lifetime& life = compiled.bufferLifetimes[id];
        if (g.buffers[id].imported || !isUsed(life)) continue;
        MemoryRequirements req = allocator.requirements(g.buffers[id].desc, g.buffers[id].usage);
        out.push_back({{false, id, 0, req.size}, std::max<VkDeviceSize>(1, req.alignment), life});
    }
    return out;
}

}  // namespace

void placeTransients(const FrameGraph::Impl& g, const ResourceAllocator& allocator,
                     CompiledGraph& compiled) {
    std::vector<Candidate> todo = gatherTransients(g, allocator, compiled);
    // Textures before buffers and lower ids first on equal sizes, so placement is stable.
    std::stable_sort(todo.begin(), todo.end(), [](const Candidate& a, const Candidate& b) {
        return a.placement.size > b.placement.size;
    });
    std::vector<Candidate> placed;
    MemoryStats stats;
    for (Candidate& c : todo) {
        c.placement.offset = firstFit(c, placed, g.config.aliasing);
        stats.transientWithAliasing =
            std::max(stats.transientWithAliasing, c.placement.offset + c.placement.size);
        stats.transientWithoutAliasing += alignUp(c.placement.size, c.alignment);
        placed.push_back(c);
    }
    // Report placements in resource order (textures, then buffers) for readable dumps.
    std::sort(placed.begin(), placed.end(), [](const Candidate& a, const Candidate& b) {
        if (a.placement.isTexture != b.placement.isTexture) return a.placement.isTexture;
        return a.placement.resource < b.placement.resource;
    });
    compiled.placements.clear();
    for (const Candidate& c : placed) compiled.placements.push_back(c.placement);
    compiled.memory = stats;
}

}  // namespace speculum
