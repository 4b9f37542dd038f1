// FrameGraph declaration API (passes, resources, versioned handles) and compile() driver.
#include "framegraph/compile_stages.hpp"

#include <cmath>

namespace speculum {
namespace {

uint32_t resolveSize(uint32_t absolute, uint32_t output, float scale) {
    if (absolute > 0) return absolute;
    double scaled = std::ceil(double(output) * double(scale));
    return scaled < 1.0 ? 1u : uint32_t(scaled);
}

// Width and height of a new texture: absolute, or relative to its `relativeTo` texture (already
// resolved: handles only name earlier textures) or to the output.
void resolveExtent(const FrameGraph::Impl& g, TextureDesc& d, const std::string& name) {
    uint32_t baseW = g.config.outputWidth, baseH = g.config.outputHeight;
    if (d.relativeTo.valid()) {
        if (d.relativeTo.id >= g.textures.size())
            throw FrameGraphError("texture '" + name + "' is sized relative to texture " +
                                  std::to_string(d.relativeTo.id) + ", which does not exist");
        const TextureDesc& base = g.textures[d.relativeTo.id].info.desc;
        baseW = base.width;
        baseH = base.height;
    }
    d.width = resolveSize(d.width, baseW, d.relativeScale);
    d.height = resolveSize(d.height, baseH, d.relativeScale);
}

uint32_t fullMipChain(uint32_t w, uint32_t h) {
    uint32_t mips = 1;
    while ((std::max(w, h) >> mips) > 0) ++mips;
    return mips;
}

bool isAttachment(TextureUsage u) {
    return u == TextureUsage::ColorAttachment || u == TextureUsage::DepthAttachment ||
           u == TextureUsage::DepthRead;
}

bool isTransfer(TextureUsage u) {
    return u == TextureUsage::TransferSrc || u == TextureUsage::TransferDst;
}

}  // namespace

// ---- PassBuilder -------------------------------------------------------------------------

namespace {

// Stale handles are the bug versioning exists to catch: a pass holding an old handle would
// otherwise silently read data from before a later write.
void checkVersion(const std::string& pass, const std::string& resource, uint32_t version,
                  uint32_t current, bool write) {
    if (version < current) {
        throw FrameGraphError("pass '" + pass + "' uses stale handle of '" + resource +
                              "' (version " + std::to_string(version) + ", current " +
                              std::to_string(current) + ")");
    }
    if (write && version > current) {
        throw FrameGraphError("pass '" + pass + "' writes '" + resource + "' through version " +
                              std::to_string(version) + " which does not exist yet (current " +
                              std::to_string(current) + ")");
    }
}

Subresource resolveRange(const std::string& pass, const TextureInfo& info, Subresource r) {
    const TextureDesc& d = info.desc;
    if (r.mipCount == kAllMips) r.mipCount = r.baseMip < d.mips ? d.mips - r.baseMip : 0;
    if (r.layerCount == kAllLayers) {
        r.layerCount = r.baseLayer < d.layers ? d.layers - r.baseLayer : 0;
    }
    if (r.mipCount == 0 || r.layerCount == 0 || uint64_t(r.baseMip) + r.mipCount > d.mips ||
        uint64_t(r.baseLayer) + r.layerCount > d.layers) {
        throw FrameGraphError("pass '" + pass + "': subresource of '" + info.name + "' (mips " +
                              std::to_string(r.baseMip) + "+" + std::to_string(r.mipCount) +
                              ", layers " + std::to_string(r.baseLayer) + "+" +
                              std::to_string(r.layerCount) + ") is outside its " +
                              std::to_string(d.mips) + " mips and " +
                              std::to_string(d.layers) + " layers");
    }
    return r;
}

TextureNode& textureFor(FrameGraph::Impl& g, const std::string& pass, TextureHandle h) {
    if (!h.valid() || h.id >= g.textures.size()) {
        throw FrameGraphError("pass '" + pass + "' uses an invalid texture handle");
    }
    return g.textures[h.id];
}

BufferNode& bufferFor(FrameGraph::Impl& g, const std::string& pass, BufferHandle h) {
    if (!h.valid() || h.id >= g.buffers.size()) {
        throw FrameGraphError("pass '" + pass + "' uses an invalid buffer handle");
    }
    return g.buffers[h.id];
}

void checkTextureUsage(const PassNode& pass, const std::string& resource, TextureUsage usage,
                       bool write) {
    if (accessOf(usage, pass.type).writes != write) {
        throw FrameGraphError("pass '" + pass.name + "' " + (write ? "writes" : "reads") + " '" +
                              resource + "' as " + usageName(usage) + ", which " +
                              (write ? "only reads; use read()" : "writes; use write()"));
    }
    if (isAttachment(usage) && pass.type != PassType::Raster) {
        throw FrameGraphError("pass '" + pass.name + "' uses '" + resource + "' as " +
                              usageName(usage) + " but is not a Raster pass");
    }
    if (pass.type == PassType::Transfer && !isTransfer(usage) &&
        usage != TextureUsage::Present) {
        throw FrameGraphError("pass '" + pass.name + "' is a Transfer pass but uses '" +
                              resource + "' as " + usageName(usage));
    }
}

}  // namespace

TextureHandle PassBuilder::create(const std::string& name, const TextureDesc& desc) {
    FrameGraph::Impl& g = *graph_.impl_;
    TextureNode node;
    node.info.name = name;
    node.info.desc = desc;
    resolveExtent(g, node.info.desc, name);
    const TextureDesc& d = node.info.desc;
    const std::string& pass = g.passes[pass_].name;
    if (d.mips == 0 || d.layers == 0 || d.mips > fullMipChain(d.width, d.height)) {
        throw FrameGraphError("pass '" + pass + "' creates '" + name + "' with " +
                              std::to_string(d.mips) + " mips and " + std::to_string(d.layers) +
                              " layers at " + std::to_string(d.width) + "x" +
                              std::to_string(d.height));
    }
    if (d.cube && (d.layers % 6 != 0 || d.width != d.height)) {
        throw FrameGraphError("pass '" + pass + "' creates cube '" + name +
                              "' that is not square with a multiple of 6 layers");
    }
    g.textures.push_back(std::move(node));
    return {uint32_t(g.textures.size() - 1), 0};
}

BufferHandle PassBuilder::create(const std::string& name, const BufferDesc& desc) {
    FrameGraph::Impl& g = *graph_.impl_;
    if (desc.size == 0) {
        throw FrameGraphError("pass '" + g.passes[pass_].name + "' creates empty buffer '" +
                              name + "'");
    }
    g.buffers.push_back(BufferNode{name, desc});
    return {uint32_t(g.buffers.size() - 1), 0};
}

TextureHandle PassBuilder::read(TextureHandle h, TextureUsage usage, Subresource range) {
    FrameGraph::Impl& g = *graph_.impl_;
    PassNode& pass = g.passes[pass_];
    TextureNode& tex = textureFor(g, pass.name, h);
    // A read may name a version later than the current one: that is how a pass can depend on
    // a later pass, which compile() then orders or reports as a cycle.
    checkVersion(pass.name, tex.info.name, h.version, tex.version, false);
    checkTextureUsage(pass, tex.info.name, usage, false);
    pass.textures.push_back({h.id, h.version, usage, resolveRange(pass.name, tex.info, range),
                             false});
    return h;
}

TextureHandle PassBuilder::write(TextureHandle h, TextureUsage usage, Subresource range) {
    FrameGraph::Impl& g = *graph_.impl_;
    PassNode& pass = g.passes[pass_];
    TextureNode& tex = textureFor(g, pass.name, h);
    checkVersion(pass.name, tex.info.name, h.version, tex.version, true);
    checkTextureUsage(pass, tex.info.name, usage, true);
    pass.textures.push_back({h.id, h.version, usage, resolveRange(pass.name, tex.info, range),
                             true});
    tex.writers.push_back(pass_);
    return {h.id, ++tex.version};
}

BufferHandle PassBuilder::read(BufferHandle h, BufferUsage usage) {
    FrameGraph::Impl& g = *graph_.impl_;
    PassNode& pass = g.passes[pass_];
    BufferNode& buf = bufferFor(g, pass.name, h);
    checkVersion(pass.name, buf.name, h.version, buf.version, false);
    if (accessOf(usage, pass.type).writes) {
        throw FrameGraphError("pass '" + pass.name + "' reads '" + buf.name + "' as " +
                              usageName(usage) + ", which writes; use write()");
    }
    pass.buffers.push_back({h.id, h.version, usage, false});
    return h;
}

BufferHandle PassBuilder::write(BufferHandle h, BufferUsage usage) {
    FrameGraph::Impl& g = *graph_.impl_;
    PassNode& pass = g.passes[pass_];
    BufferNode& buf = bufferFor(g, pass.name, h);
    checkVersion(pass.name, buf.name, h.version, buf.version, true);
    if (!accessOf(usage, pass.type).writes) {
        throw FrameGraphError("pass '" + pass.name + "' writes '" + buf.name + "' as " +
                              usageName(usage) + ", which only reads; use read()");
    }
    pass.buffers.push_back({h.id, h.version, usage, true});
    buf.writers.push_back(pass_);
    return {h.id, ++buf.version};
}

void PassBuilder::sideEffect() { graph_.impl_->passes[pass_].sideEffect = true; }

// ---- FrameGraph --------------------------------------------------------------------------

FrameGraph::FrameGraph(FrameGraphConfig config) : impl_(std::make_unique<Impl>()) {
    impl_->config = config;
    impl_->config.outputWidth = std::max(1u, config.outputWidth);
    impl_->config.outputHeight = std::max(1u, config.outputHeight);
}

FrameGraph::~FrameGraph() = default;

uint32_t FrameGraph::beginPass(const std::string& name, PassType type) {
    impl_->isCompiled = false;
    impl_->passes.push_back(PassNode{name, type});
    return uint32_t(impl_->passes.size() - 1);
}

void FrameGraph::setExecute(uint32_t pass, std::function<void(PassContext&)> fn) {
    impl_->passes.at(pass).execute = std::move(fn);
}

TextureHandle FrameGraph::importTexture(const std::string& name, const TextureDesc& desc,
                                        const ImportedTexture& texture) {
    TextureNode node;
    node.info.name = name;
    node.info.desc = desc;
    resolveExtent(*impl_, node.info.desc, name);
    node.info.desc.mips = std::max(1u, desc.mips);
    node.info.desc.layers = std::max(1u, desc.layers);
    node.info.usage = texture.usage;
    node.info.imported = true;
    node.imported = texture;
    impl_->textures.push_back(std::move(node));
    impl_->isCompiled = false;
    return {uint32_t(impl_->textures.size() - 1), 0};
}

HistoryHandles FrameGraph::importHistory(const std::string& name, History& history) {
    constexpr VkImageLayout kReadOnly = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    HistoryHandles h;
    h.valid = history.valid();
    h.previous = importTexture(name + ".previous", history.desc_,
                               {history.previousImage(), kReadOnly, kReadOnly, history.usage_});
    // The current image's old content is discarded: it is written whole this frame.
    h.current = importTexture(name + ".current", history.desc_,
                              {history.currentImage(), VK_IMAGE_LAYOUT_UNDEFINED, kReadOnly, history.usage_});
    impl_->histories.emplace_back(&history, h.current.id);
    return h;
}

BufferHandle FrameGraph::importBuffer(const std::string& name, const BufferDesc& desc,
                                      const ImportedBuffer& buffer) {
    BufferNode node{name, desc};
    node.imported = buffer;
    impl_->buffers.push_back(std::move(node));
    impl_->isCompiled = false;
    return {uint32_t(impl_->buffers.size() - 1), 0};
}

void FrameGraph::markOutput(TextureHandle h) {
    if (!h.valid() || h.id >= impl_->textures.size()) {
        throw FrameGraphError("markOutput: invalid texture handle");
    }
    impl_->textures[h.id].output = true;
    impl_->isCompiled = false;
}

void FrameGraph::markOutput(BufferHandle h) {
    if (!h.valid() || h.id >= impl_->buffers.size()) {
        throw FrameGraphError("markOutput: invalid buffer handle");
    }
    impl_->buffers[h.id].output = true;
    impl_->isCompiled = false;
}

const CompiledGraph& FrameGraph::compile(const ResourceAllocator& allocator) {
    Impl& g = *impl_;
    validateGraph(g);
    PassEdges edges = buildEdges(g);
    std::vector<uint32_t> order = orderPasses(g, edges);

    CompiledGraph compiled;
    compiled.passCulled = cullPasses(g, edges);
    for (uint32_t p : order) {
        if (!compiled.passCulled[p]) compiled.passes.push_back(CompiledPass{p});
    }
    computeUsage(g, compiled.passCulled);
    computeLifetimes(g, compiled);
    placeTransients(g, allocator, compiled);
    deriveBarriers(g, compiled);

    g.compiled = std::move(compiled);
    g.isCompiled = true;
    ++g.generation;
    return g.compiled;
}

const CompiledGraph& FrameGraph::compiled() const {
    if (!impl_->isCompiled) throw FrameGraphError("the frame graph has not been compiled");
    return impl_->compiled;
}

const FrameGraphConfig& FrameGraph::config() const { return impl_->config; }
uint32_t FrameGraph::passCount() const { return uint32_t(impl_->passes.size()); }
const std::string& FrameGraph::passName(uint32_t pass) const { return impl_->passes.at(pass).name; }
PassType FrameGraph::passType(uint32_t pass) const { return impl_->passes.at(pass).type; }
uint32_t FrameGraph::textureCount() const { return uint32_t(impl_->textures.size()); }
const TextureInfo& FrameGraph::texture(uint32_t id) const { return impl_->textures.at(id).info; }

const ImportedTexture* FrameGraph::importedTexture(uint32_t id) const {
    const auto& imported = impl_->textures.at(id).imported;
    return imported ? &*imported : nullptr;
}

uint32_t FrameGraph::bufferCount() const { return uint32_t(impl_->buffers.size()); }
const std::string& FrameGraph::bufferName(uint32_t id) const { return impl_->buffers.at(id).name; }
const BufferDesc& FrameGraph::bufferDesc(uint32_t id) const { return impl_->buffers.at(id).desc; }
VkBufferUsageFlags FrameGraph::bufferUsage(uint32_t id) const {
    return impl_->buffers.at(id).usage;
}

const ImportedBuffer* FrameGraph::importedBuffer(uint32_t id) const {
    const auto& imported = impl_->buffers.at(id).imported;
    return imported ? &*imported : nullptr;
}

// ---- PassContext -------------------------------------------------------------------------

VkImage PassContext::image(TextureHandle h) const { return exec_.image(h.id); }

VkImageView PassContext::view(TextureHandle h, Subresource range) const {
    const TextureDesc& d = info(h).desc;
    uint32_t layers = range.layerCount == kAllLayers ? d.layers - range.baseLayer
                                                     : range.layerCount;
    VkImageViewType type = VK_IMAGE_VIEW_TYPE_2D;
    if (d.cube && layers % 6 == 0) {
        type = layers == 6 ? VK_IMAGE_VIEW_TYPE_CUBE : VK_IMAGE_VIEW_TYPE_CUBE_ARRAY;
    } else if (layers > 1) {
        type = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
    }
    return exec_.view(h.id, range, type);
}

VkImageView PassContext::view(TextureHandle h, Subresource range, VkImageViewType type) const {
    return exec_.view(h.id, range, type);
}

VkBuffer PassContext::buffer(BufferHandle h) const { return exec_.buffer(h.id); }
const TextureInfo& PassContext::info(TextureHandle h) const { return graph_.texture(h.id); }

VkExtent2D PassContext::extent(TextureHandle h, uint32_t mip) const {
    const TextureDesc& d = info(h).desc;
    return {mipExtent(d.width, mip), mipExtent(d.height, mip)};
}

}  // namespace speculum
