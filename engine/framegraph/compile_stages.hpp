// The stages of FrameGraph::compile(), each in its own file. All are pure CPU; compile() runs
// them in the order listed here. User errors are thrown as FrameGraphError naming pass and
// resource.
#pragma once

#include "framegraph/graph_impl.hpp"

#include <vector>

namespace speculum {

struct PassEdges {
    // needs[p]: passes whose results p consumes (producers of the versions p reads, and of the
    // version p writes over, since a partial write keeps the rest of the resource). Culling
    // follows these.
    std::vector<std::vector<uint32_t>> needs;
    // after[p]: every pass that must run before p: needs plus write-after-read (a writer runs
    // after the readers of the version it overwrites). Ordering follows these.
    std::vector<std::vector<uint32_t>> after;
};

// validate.cpp: reads of versions nobody writes, and attachments of different extents.
void validateGraph(const FrameGraph::Impl& graph);

// edges.cpp
PassEdges buildEdges(const FrameGraph::Impl& graph);

// order.cpp: a topological order of all declared passes that keeps declaration order where
// dependencies allow. Throws "cycle between passes 'a' and 'b'".
std::vector<uint32_t> orderPasses(const FrameGraph::Impl& graph, const PassEdges& edges);

// cull.cpp: true for passes that nothing needs. Roots are sideEffect passes, producers of
// markOutput resources and passes that write imported resources (an imported resource lives
// beyond the frame, so writing it is an output).
std::vector<bool> cullPasses(const FrameGraph::Impl& graph, const PassEdges& edges);

// lifetimes.cpp: TextureInfo::usage and BufferNode::usage as the union over surviving passes.
void computeUsage(FrameGraph::Impl& graph, const std::vector<bool>& culled);

// lifetimes.cpp: first/last execution index of every resource used by a surviving pass.
// Unused resources get kUnusedLifetime.
inline constexpr Lifetime kUnusedLifetime{std::numeric_limits<uint32_t>::max(), 0};
inline bool isUsed(const Lifetime& l) { return l.first <= l.last; }
void computeLifetimes(const FrameGraph::Impl& graph, CompiledGraph& compiled);

// aliasing.cpp: places used transients in one heap and fills MemoryStats.
void placeTransients(const FrameGraph::Impl& graph, const ResourceAllocator& allocator,
                     CompiledGraph& compiled);

// barriers.cpp: barriers before every surviving pass and the final ones for imports.
void deriveBarriers(const FrameGraph::Impl& graph, CompiledGraph& compiled);

}  // namespace speculum
