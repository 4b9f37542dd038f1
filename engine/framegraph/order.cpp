// Execution order. Handles flow forward, so declaration order is usually already valid; a read
// of a later version is the exception, and it either moves its producer earlier or closes a
// cycle.
#include "framegraph/compile_stages.hpp"

#include <algorithm>
#include <functional>
#include <queue>

namespace speculum {
namespace {

// Walks "must run after" edges among the unscheduled passes until one repeats. Reports the
// first-declared pass on that cycle and the pass it waits on.
[[noreturn]] void reportCycle(const FrameGraph::Impl& g, const PassEdges& e,
                              const std::vector<uint32_t>& pending) {
    std::vector<int> seenAt(g.passes.size(), -1);
    std::vector<uint32_t> path;
    uint32_t p = uint32_t(std::find_if(pending.begin(), pending.end(),
                                       [](uint32_t n) { return n > 0; }) - pending.begin());
    while (seenAt[p] < 0) {
        seenAt[p] = int(path.size());
        path.push_back(p);
        for (uint32_t dep : e.after[p]) {
            if (pending[dep] > 0) {
                p = dep;
                break;
            }
        }
    }
    std::vector<uint32_t> cycle(path.begin() + seenAt[p], path.end());
    auto first = std::min_element(cycle.begin(), cycle.end());
    uint32_t waitsOn = (first + 1 == cycle.end()) ? cycle.front() : *(first + 1);
    throw FrameGraphError("cycle between passes '" + g.passes[*first].name + "' and '" +
                          g.passes[waitsOn].name + "'");
}

}  // namespace

std::vector<uint32_t> orderPasses(const FrameGraph::Impl& g, const PassEdges& e) {
    const size_t n = g.passes.size();
    std::vector<uint32_t> pending(n, 0);  // unscheduled predecessors per pass
    std::vector<std::vector<uint32_t>> successors(n);
    for (uint32_t p = 0; p < n; ++p) {
        pending[p] = uint32_t(e.after[p].size());
        for (uint32_t dep : e.after[p]) successors[dep].push_back(p);
    }
    // Kahn's algorithm, always taking the first-declared ready pass, so that the result is
    // declaration order whenever that order is valid.
    std::priority_queue<uint32_t, std::vector<uint32_t>, std::greater<>> ready;
    for (uint32_t p = 0; p < n; ++p) {
        if (pending[p] == 0) ready.push(p);
    }
    std::vector<uint32_t> order;
    order.reserve(n);
    while (!ready.empty()) {
        uint32_t p = ready.top();
        ready.pop();
        order.push_back(p);
        for (uint32_t s : successors[p]) {
            if (--pending[s] == 0) ready.push(s);
        }
    }
    if (order.size() != n) reportCycle(g, e, pending);
    return order;
}

}  // namespace speculum
