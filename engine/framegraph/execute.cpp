// FrameGraph::execute(): realize resources when the compiled graph changed, then record every
// surviving pass between the executor's label/timestamp brackets, barriers first.
#include "framegraph/graph_impl.hpp"

namespace speculum {
namespace {

void recordBarriers(const FrameGraph& graph, FrameGraphExecutor& executor, VkCommandBuffer cmd,
                    const std::vector<TextureBarrier>& textures,
                    const std::vector<BufferBarrier>& buffers) {
    if (textures.empty() && buffers.empty()) return;
    std::vector<VkImageMemoryBarrier2> images;
    images.reserve(textures.size());
    for (const TextureBarrier& b : textures) {
        VkImageMemoryBarrier2 ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
        ib.srcStageMask = b.srcStage;
        ib.srcAccessMask = b.srcAccess;
        ib.dstStageMask = b.dstStage;
        ib.dstAccessMask = b.dstAccess;
        ib.oldLayout = b.oldLayout;
        ib.newLayout = b.newLayout;
        ib.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        ib.image = executor.image(b.texture);
        ib.subresourceRange = {aspectOf(graph.texture(b.texture).desc.format), b.range.baseMip,
                               b.range.mipCount, b.range.baseLayer, b.range.layerCount};
        images.push_back(ib);
    }
    std::vector<VkBufferMemoryBarrier2> bufs;
    bufs.reserve(buffers.size());
    for (const BufferBarrier& b : buffers) {
        VkBufferMemoryBarrier2 bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
        bb.srcStageMask = b.srcStage;
        bb.srcAccessMask = b.srcAccess;
        bb.dstStageMask = b.dstStage;
        bb.dstAccessMask = b.dstAccess;
        bb.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        bb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        bb.buffer = executor.buffer(b.buffer);
        bb.offset = 0;
        bb.size = VK_WHOLE_SIZE;
        bufs.push_back(bb);
    }
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = uint32_t(images.size());
    dep.pImageMemoryBarriers = images.data();
    dep.bufferMemoryBarrierCount = uint32_t(bufs.size());
    dep.pBufferMemoryBarriers = bufs.data();
    vkCmdPipelineBarrier2(cmd, &dep);
}

}  // namespace

void FrameGraph::execute(FrameGraphExecutor& executor, VkCommandBuffer cmd) {
    Impl& g = *impl_;
    if (!g.isCompiled) throw FrameGraphError("execute() called before compile()");
    if (g.realizedBy != &executor || g.realizedGeneration != g.generation) {
        executor.realize(*this, g.compiled);
        g.realizedBy = &executor;
        g.realizedGeneration = g.generation;
    }
    PassContext ctx(*this, executor, cmd);
    for (uint32_t i = 0; i < g.compiled.passes.size(); ++i) {
        const CompiledPass& cp = g.compiled.passes[i];
        const PassNode& pass = g.passes[cp.pass];
        // Barriers go inside the label and timestamps so their cost is charged to the pass.
        executor.beginPass(cmd, pass.name, i);
        recordBarriers(*this, executor, cmd, cp.textureBarriers, cp.bufferBarriers);
        if (pass.execute) pass.execute(ctx);
        executor.endPass(cmd, i);
    }
    recordBarriers(*this, executor, cmd, g.compiled.finalTextureBarriers, {});
    commitHistories();
}

void FrameGraph::commitHistories() {
    Impl& g = *impl_;
    if (!g.isCompiled) throw FrameGraphError("commitHistories() called before compile()");
    for (auto [history, id] : g.histories) {
        const TextureNode& node = g.textures[id];
        bool written = std::any_of(node.writers.begin(), node.writers.end(),
                                   [&](uint32_t pass) { return !g.compiled.passCulled[pass]; });
        if (written) history->current_ = 1 - history->current_;
        history->valid_ = written;
    }
    g.histories.clear();  // a second execute() of the same graph must not swap again
}

}  // namespace speculum
