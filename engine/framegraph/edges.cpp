// Dependencies between passes, derived from the versions they read and write.
#include "framegraph/compile_stages.hpp"

#include <algorithm>

namespace speculum {
namespace {

void addUnique(std::vector<uint32_t>& list, uint32_t pass) {
    if (std::find(list.begin(), list.end(), pass) == list.end()) list.push_back(pass);
}

// Readers of each version of one resource: readers[v] lists the passes that read version v.
using VersionReaders = std::vector<std::vector<uint32_t>>;

void addAccess(PassEdges& e, uint32_t pass, uint32_t version, bool write,
               const std::vector<uint32_t>& writers, VersionReaders& readers) {
    // The producer of the version used. A pass's uses of its own results are internal to it.
    if (version > 0 && version <= writers.size() && writers[version - 1] != pass) {
        addUnique(e.needs[pass], writers[version - 1]);
        addUnique(e.after[pass], writers[version - 1]);
    }
    if (readers.size() <= version) readers.resize(version + 1);
    if (!write) addUnique(readers[version], pass);
}

// A writer of version v -> v+1 must not overwrite what readers of version v still need.
void addWriteAfterRead(PassEdges& e, uint32_t pass, uint32_t version,
                       const VersionReaders& readers) {
    if (version >= readers.size()) return;
    for (uint32_t reader : readers[version]) {
        if (reader != pass) addUnique(e.after[pass], reader);
    }
}

}  // namespace

PassEdges buildEdges(const FrameGraph::Impl& g) {
    PassEdges e;
    e.needs.resize(g.passes.size());
    e.after.resize(g.passes.size());
    std::vector<VersionReaders> texReaders(g.textures.size());
    std::vector<VersionReaders> bufReaders(g.buffers.size());
    for (uint32_t p = 0; p < g.passes.size(); ++p) {
        for (const TextureAccess& a : g.passes[p].textures) {
            addAccess(e, p, a.version, a.write, g.textures[a.texture].writers,
                      texReaders[a.texture]);
        }
        for (const BufferAccess& a : g.passes[p].buffers) {
            addAccess(e, p, a.version, a.write, g.buffers[a.buffer].writers,
                      bufReaders[a.buffer]);
        }
    }
    // Second sweep: all readers are known now, including ones that name future versions.
    for (uint32_t p = 0; p < g.passes.size(); ++p) {
        for (const TextureAccess& a : g.passes[p].textures) {
            if (a.write) addWriteAfterRead(e, p, a.version, texReaders[a.texture]);
        }
        for (const BufferAccess& a : g.passes[p].buffers) {
            if (a.write) addWriteAfterRead(e, p, a.version, bufReaders[a.buffer]);
        }
    }
    return e;
}

}  // namespace speculum
