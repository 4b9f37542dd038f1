// Culling: a pass survives when something outside the graph can observe its results.
#include "framegraph/compile_stages.hpp"

namespace speculum {

std::vector<bool> cullPasses(const FrameGraph::Impl& g, const PassEdges& e) {
    std::vector<bool> alive(g.passes.size(), false);
    std::vector<uint32_t> stack;
    auto keep = [&](uint32_t p) {
        if (!alive[p]) {
            alive[p] = true;
            stack.push_back(p);
        }
    };
    for (uint32_t p = 0; p < g.passes.size(); ++p) {
        const PassNode& pass = g.passes[p];
        if (pass.sideEffect) keep(p);
        // Imported resources outlive the frame (history, swapchain), so writing one is an
        // output even without markOutput.
        for (const TextureAccess& a : pass.textures) {
            if (a.write && g.textures[a.texture].imported) keep(p);
        }
        for (const BufferAccess& a : pass.buffers) {
            if (a.write && g.buffers[a.buffer].imported) keep(p);
        }
    }
    // markOutput keeps the last writer; partial writes chain back to earlier writers via needs.
    for (const TextureNode& t : g.textures) {
        if (t.output && !t.writers.empty()) keep(t.writers.back());
    }
    for (const BufferNode& b : g.buffers) {
        if (b.output && !b.writers.empty()) keep(b.writers.back());
    }
    while (!stack.empty()) {
        uint32_t p = stack.back();
        stack.pop_back();
        for (uint32_t dep : e.needs[p]) keep(dep);
    }
    std::vector<bool> culled(g.passes.size());
    for (size_t p = 0; p < culled.size(); ++p) culled[p] = !alive[p];
    return culled;
}

}  // namespace speculum
