// User errors found before any scheduling: reads of data nobody produces and attachments of
// different sizes in one pass. Checked on every declared pass, culled or not, so an error does
// not appear or vanish depending on which outputs happen to be marked.
#include "framegraph/compile_stages.hpp"

namespace speculum {
namespace {

std::string extentString(uint32_t w, uint32_t h) {
    return std::to_string(w) + "x" + std::to_string(h);
}

// Version v of a resource exists when some pass wrote version v-1; version 0 of an import is
// its contents from outside the frame, version 0 of a transient is garbage.
void checkProduced(const std::string& pass, const std::string& resource, uint32_t version,
                   size_t writes, bool imported) {
    if (version == 0 && !imported) {
        throw FrameGraphError("pass '" + pass + "' reads '" + resource +
                              "' before any pass writes it");
    }
    if (version > writes) {
        throw FrameGraphError("pass '" + pass + "' reads version " + std::to_string(version) +
                              " of '" + resource + "' but no pass produces it");
    }
}

void checkAttachmentExtents(const FrameGraph::Impl& g, const PassNode& pass) {
    const TextureAccess* first = nullptr;
    uint32_t fw = 0, fh = 0;
    for (const TextureAccess& a : pass.textures) {
        if (a.usage != TextureUsage::ColorAttachment && a.usage != TextureUsage::DepthAttachment &&
            a.usage != TextureUsage::DepthRead) {
            continue;
        }
        const TextureDesc& d = g.textures[a.texture].info.desc;
        uint32_t w = mipExtent(d.width, a.range.baseMip);
        uint32_t h = mipExtent(d.height, a.range.baseMip);
        if (!first) {
            first = &a;
            fw = w;
            fh = h;
        } else if (w != fw || h != fh) {
            throw FrameGraphError("pass '" + pass.name + "': attachment '" +
                                  textureName(g, first->texture) + "' is " +
                                  extentString(fw, fh) + " but '" + textureName(g, a.texture) +
                                  "' is " + extentString(w, h));
        }
    }
}

}  // namespace

void validateGraph(const FrameGraph::Impl& g) {
    for (const PassNode& pass : g.passes) {
        for (const TextureAccess& a : pass.textures) {
            if (a.write) continue;
            const TextureNode& t = g.textures[a.texture];
            checkProduced(pass.name, t.info.name, a.version, t.writers.size(),
                          t.imported.has_value());
        }
        for (const BufferAccess& a : pass.buffers) {
            if (a.write) continue;
            const BufferNode& b = g.buffers[a.buffer];
            checkProduced(pass.name, b.name, a.version, b.writers.size(), b.imported.has_value());
        }
        checkAttachmentExtents(g, pass);
    }
}

}  // namespace speculum
