// Barrier derivation (synchronization2). Every (texture, mip, layer) and every buffer carries
// a SyncState; each use either is already covered by it or needs one barrier. The rules:
//  - A write or a layout transition waits on the readers since the last write, or on the last
//    write itself when nothing read it, and makes that write available if no barrier has yet.
//  - A read in the current layout needs a barrier only when the last write is not yet visible
//    to its stage and access; read-after-read in one layout needs nothing.
//  - A transient starts UNDEFINED. When it shares memory with transients that died before it,
//    its first barriers also wait on their last uses (an aliasing barrier).
//  - An import starts in initialLayout, written by "something before the frame":
//    ALL_COMMANDS / MEMORY_WRITE (no access when initialLayout is UNDEFINED).
//  - Final barriers move imports to finalLayout; towards PRESENT_SRC_KHR nothing in the queue
//    waits (the present semaphore does), otherwise ALL_COMMANDS waits.
#include "framegraph/compile_stages.hpp"

#include <algorithm>
#include <map>
#include <tuple>

namespace speculum {
namespace {

constexpr VkAccessFlags2 kWriteAccess =
    VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
    VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
    VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_HOST_WRITE_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;

struct SyncState {
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkPipelineStageFlags2 writeStage = 0;   // last write, or the dst stage of the last transition
    VkAccessFlags2 pendingWrite = 0;        // write access not yet made available
    VkPipelineStageFlags2 readStages = 0;   // stages that read since the last write/transition
    VkPipelineStageFlags2 visibleStages = 0;
    VkAccessFlags2 visibleAccess = 0;
};

struct Sync {
    VkPipelineStageFlags2 srcStage = 0;
    VkAccessFlags2 srcAccess = 0;
    VkImageLayout oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
};

// Applies one use to the state; returns true (and the source half) when it needs a barrier.
bool apply(SyncState& s, const AccessInfo& use, bool hasLayout, Sync& sync) {
    const bool transition = hasLayout && s.layout != use.layout;
    bool needed = false;
    if (transition || use.writes) {
        sync = {s.readStages ? s.readStages : s.writeStage, s.pendingWrite, s.layout};
        needed = transition || sync.srcStage != 0 || sync.srcAccess != 0;
    } else {
        bool visible = (use.stage & ~s.visibleStages) == 0 && (use.access & ~s.visibleAccess) == 0;
        bool written = s.writeStage != 0 || s.pendingWrite != 0;
        sync = {s.writeStage, s.pendingWrite, s.layout};
        needed = written && !visible;
    }
    if (use.writes) {
        s = {use.layout, use.stage, use.access & kWriteAccess, 0, 0, 0};
    } else if (transition) {
        // Later users chain on the transition through the stage it was made visible to.
        s = {use.layout, use.stage, 0, use.stage, use.stage, use.access};
    } else if (needed) {
        s.pendingWrite = 0;
        s.readStages |= use.stage;
        s.visibleStages |= use.stage;
        s.visibleAccess |= use.access;
    } else {
        s.readStages |= use.stage;
    }
    return needed;
}

struct TextureBarrierLess {
    bool operator()(const TextureBarrier& a, const TextureBarrier& b) const {
        return std::tie(a.texture, a.range.baseLayer, a.range.baseMip) <
               std::tie(b.texture, b.range.baseLayer, b.range.baseMip);
    }
};

bool sameTransition(TextureBarrier a, const TextureBarrier& b) {
    a.range = b.range;
    return a == b;
}

// Merges barriers of adjacent mips (then adjacent layers) that do the same thing.
std::vector<TextureBarrier> mergeRanges(std::vector<TextureBarrier> in) {
    std::sort(in.begin(), in.end(), TextureBarrierLess{});
    std::vector<TextureBarrier> mips;
    for (const TextureBarrier& b : in) {
        if (!mips.empty()) {
            TextureBarrier& prev = mips.back();
            if (sameTransition(prev, b) && prev.range.baseLayer == b.range.baseLayer &&
                prev.range.layerCount == b.range.layerCount &&
                prev.range.baseMip + prev.range.mipCount == b.range.baseMip) {
                prev.range.mipCount += b.range.mipCount;
                continue;
            }
        }
        mips.push_back(b);
    }
    std::stable_sort(mips.begin(), mips.end(), [](const auto& a, const auto& b) {
        return std::tie(a.texture, a.range.baseMip, a.range.mipCount, a.range.baseLayer) <
               std::tie(b.texture, b.range.baseMip, b.range.mipCount, b.range.baseLayer);
    });
    std::vector<TextureBarrier> out;
    for (const TextureBarrier& b : mips) {
        if (!out.empty()) {
            TextureBarrier& prev = out.back();
            if (sameTransition(prev, b) && prev.range.baseMip == b.range.baseMip &&
                prev.range.mipCount == b.range.mipCount &&
                prev.range.baseLayer + prev.range.layerCount == b.range.baseLayer) {
                prev.range.layerCount += b.range.layerCount;
                continue;
            }
        }
        out.push_back(b);
    }
    std::sort(out.begin(), out.end(), TextureBarrierLess{});
    return out;
}

class BarrierBuilder {
public:
    BarrierBuilder(const FrameGraph::Impl& g, CompiledGraph& c) : g_(g), c_(c) {
        tex_.resize(g.textures.size());
        buf_.resize(g.buffers.size());
        texPlacement_.assign(g.textures.size(), -1);
        bufPlacement_.assign(g.buffers.size(), -1);
        for (size_t i = 0; i < c.placements.size(); ++i) {
            const Placement& p = c.placements[i];
            (p.isTexture ? texPlacement_ : bufPlacement_)[p.resource] = int(i);
        }
    }

    void pass(CompiledPass& out);
    void finalBarriers();

private:
    using Key = std::tuple<uint32_t, uint32_t, uint32_t>;  // texture, layer, mip

    std::vector<SyncState>& textureStates(uint32_t id);
    SyncState& bufferState(uint32_t id);
    SyncState initialState(bool isTexture, uint32_t id) const;
    Sync lastUses(bool isTexture, uint32_t id) const;
    std::map<Key, AccessInfo> gatherTextureUses(const PassNode& pass) const;

    const FrameGraph::Impl& g_;
    CompiledGraph& c_;
    std::vector<std::vector<SyncState>> tex_;  // per texture, [layer * mips + mip]; lazily
    std::vector<std::vector<SyncState>> buf_;  // per buffer, zero or one state
    std::vector<int> texPlacement_, bufPlacement_;
};

// What a resource placed at the same memory and already dead was last doing.
Sync BarrierBuilder::lastUses(bool isTexture, uint32_t id) const {
    Sync s;
    for (const SyncState& st : isTexture ? tex_[id] : buf_[id]) {
        s.srcStage |= st.readStages ? st.readStages : st.writeStage;
        s.srcAccess |= st.pendingWrite;
    }
    return s;
}

SyncState BarrierBuilder::initialState(bool isTexture, uint32_t id) const {
    SyncState s;
    bool imported = isTexture ? g_.textures[id].imported.has_value()
                              : g_.buffers[id].imported.has_value();
    if (imported) {
        s.layout = isTexture ? g_.textures[id].imported->initialLayout : s.layout;
        s.writeStage = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
        bool discarded = isTexture && s.layout == VK_IMAGE_LAYOUT_UNDEFINED;
        s.pendingWrite = discarded ? 0 : VK_ACCESS_2_MEMORY_WRITE_BIT;
        return s;
    }
    int self = (isTexture ? texPlacement_ : bufPlacement_)[id];
    if (self < 0) return s;
    const Placement& me = c_.placements[self];
    const Lifetime& life = isTexture ? c_.textureLifetimes[id] : c_.bufferLifetimes[id];
    for (const Placement& other : c_.placements) {
        const Lifetime& ol = other.isTexture ? c_.textureLifetimes[other.resource]
                                             : c_.bufferLifetimes[other.resource];
        bool memoryOverlap =
            other.offset < me.offset + me.size && me.offset < other.offset + other.size;
        if (&other == &me || !memoryOverlap || ol.last >= life.first) continue;
        Sync prev = lastUses(other.isTexture, other.resource);
        s.writeStage |= prev.srcStage;
        s.pendingWrite |= prev.srcAccess;
    }
    return s;
}

std::vector<SyncState>& BarrierBuilder::textureStates(uint32_t id) {
    if (tex_[id].empty()) {
        const TextureDesc& d = g_.textures[id].info.desc;
        tex_[id].assign(size_t(d.mips) * d.layers, initialState(true, id));
    }
    return tex_[id];
}

SyncState& BarrierBuilder::bufferState(uint32_t id) {
    if (buf_[id].empty()) buf_[id].push_back(initialState(false, id));
    return buf_[id][0];
}

std::map<BarrierBuilder::Key, AccessInfo>
BarrierBuilder::gatherTextureUses(const PassNode& pass) const {
    std::map<Key, AccessInfo> uses;
    for (const TextureAccess& a : pass.textures) {
        AccessInfo info = accessOf(a.usage, pass.type);
        for (uint32_t l = a.range.baseLayer; l < a.range.baseLayer + a.range.layerCount; ++l) {
            for (uint32_t m = a.range.baseMip; m < a.range.baseMip + a.range.mipCount; ++m) {
                auto [it, inserted] = uses.try_emplace(Key{a.texture, l, m}, info);
                if (inserted) continue;
                AccessInfo& u = it->second;
                if (u.layout != info.layout) {
                    throw FrameGraphError(
                        "pass '" + pass.name + "' uses '" + textureName(g_, a.texture) +
                        "' (mip " + std::to_string(m) + ", layer " + std::to_string(l) +
                        ") in both " + layoutName(u.layout) + " and " + layoutName(info.layout));
                }
                u.stage |= info.stage;
                u.access |= info.access;
                u.writes = u.writes || info.writes;
            }
        }
    }
    return uses;
}

void BarrierBuilder::pass(CompiledPass& out) {
    const PassNode& pass = g_.passes[out.pass];
    std::vector<TextureBarrier> barriers;
    for (const auto& [key, use] : gatherTextureUses(pass)) {
        auto [texture, layer, mip] = key;
        std::vector<SyncState>& states = textureStates(texture);
        const uint32_t mips = g_.textures[texture].info.desc.mips;
        Sync sync;
        if (apply(states[size_t(layer) * mips + mip], use, true, sync)) {
            barriers.push_back({texture, {mip, 1, layer, 1}, sync.srcStage, sync.srcAccess,
                                use.stage, use.access, sync.oldLayout, use.layout});
        }
    }
    out.textureBarriers = mergeRanges(std::move(barriers));

    std::map<uint32_t, AccessInfo> bufferUses;
    for (const BufferAccess& a : pass.buffers) {
        AccessInfo info = accessOf(a.usage, pass.type);
        auto [it, inserted] = bufferUses.try_emplace(a.buffer, info);
        if (!inserted) {
            it->second.stage |= info.stage;
            it->second.access |= info.access;
            it->second.writes = it->second.writes || info.writes;
        }
    }
    out.bufferBarriers.clear();
    for (const auto& [buffer, use] : bufferUses) {
        Sync sync;
        if (apply(bufferState(buffer), use, false, sync)) {
            out.bufferBarriers.push_back(
                {buffer, sync.srcStage, sync.srcAccess, use.stage, use.access});
        }
    }
}

void BarrierBuilder::finalBarriers() {
    std::vector<TextureBarrier> barriers;
    for (uint32_t id = 0; id < g_.textures.size(); ++id) {
        const auto& imported = g_.textures[id].imported;
        if (!imported || imported->finalLayout == VK_IMAGE_LAYOUT_UNDEFINED) continue;
        AccessInfo use{imported->finalLayout == VK_IMAGE_LAYOUT_PRESENT_SRC_KHR
                           ? VK_PIPELINE_STAGE_2_NONE
                           : VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                       VK_ACCESS_2_NONE, imported->finalLayout, false};
        std::vector<SyncState>& states = textureStates(id);
        const uint32_t mips = g_.textures[id].info.desc.mips;
        for (uint32_t i = 0; i < states.size(); ++i) {
            Sync sync;
            if (states[i].layout == use.layout || !apply(states[i], use, true, sync)) continue;
            barriers.push_back({id, {i % mips, 1, i / mips, 1}, sync.srcStage, sync.srcAccess,
                                use.stage, use.access, sync.oldLayout, use.layout});
        }
    }
    c_.finalTextureBarriers = mergeRanges(std::move(barriers));
}

}  // namespace

void deriveBarriers(const FrameGraph::Impl& graph, CompiledGraph& compiled) {
    BarrierBuilder builder(graph, compiled);
    for (CompiledPass& pass : compiled.passes) builder.pass(pass);
    builder.finalBarriers();
}

}  // namespace speculum
