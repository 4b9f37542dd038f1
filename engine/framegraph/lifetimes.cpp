// Resource lifetimes in execution order, and the image/buffer usage flags they need.
#include "framegraph/compile_stages.hpp"

namespace speculum {

void computeUsage(FrameGraph::Impl& g, const std::vector<bool>& culled) {
    for (TextureNode& t : g.textures) t.info.usage = t.imported ? t.imported->usage : 0;
    for (BufferNode& b : g.buffers) b.usage = 0;
    for (uint32_t p = 0; p < g.passes.size(); ++p) {
        if (culled[p]) continue;
        for (const TextureAccess& a : g.passes[p].textures) {
            g.textures[a.texture].info.usage |= imageUsageOf(a.usage);
        }
        for (const BufferAccess& a : g.passes[p].buffers) {
            g.buffers[a.buffer].usage |= bufferUsageOf(a.usage);
        }
    }
}

void computeLifetimes(const FrameGraph::Impl& g, CompiledGraph& compiled) {
    compiled.textureLifetimes.assign(g.textures.size(), kUnusedLifetime);
    compiled.bufferLifetimes.assign(g.buffers.size(), kUnusedLifetime);
    auto touch = [](Lifetime& l, uint32_t index) {
        if (!isUsed(l)) l.first = index;
        l.last = index;
    };
    for (uint32_t i = 0; i < compiled.passes.size(); ++i) {
        const PassNode& pass = g.passes[compiled.passes[i].pass];
        for (const TextureAccess& a : pass.textures) touch(compiled.textureLifetimes[a.texture], i);
        for (const BufferAccess& a : pass.buffers) touch(compiled.bufferLifetimes[a.buffer], i);
    }
}

}  // namespace speculum
