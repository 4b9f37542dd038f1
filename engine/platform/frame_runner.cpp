#include "speculum/app/frame_runner.hpp"

#include "speculum/core.hpp"
#include "speculum/gpu/fg_executor.hpp"
#include "speculum/gpu/resources.hpp"

#include <algorithm>
#include <cstring>

namespace speculum::app {

const std::vector<std::string>& availableAovs() {
    static const std::vector<std::string> k{"linear", "color", "depth", "normal", "roughness", "motion"};
    return k;
}

struct FrameRunner::Impl {
    const gpu::Context& ctx;
    render::Renderer& renderer;
    uint32_t width, height;
    gpu::VulkanResourceAllocator allocator;
    gpu::VulkanFrameGraphExecutor executor;
    gpu::Unique<VkCommandPool> pool;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    gpu::Unique<VkFence> fence;
    std::map<std::string, gpu::Buffer> readback;
    std::unique_ptr<FrameGraph> lastGraph;  // kept for dumps; its passes reference nothing on the GPU

    Impl(const gpu::Context& c, render::Renderer& r, uint32_t w, uint32_t h)
        : ctx(c), renderer(r), width(w), height(h), allocator(c.physicalDevice(), c.device()),
          executor(c.instance(), c.physicalDevice(), c.device(), c.timestampPeriodNs()) {
        VkCommandPoolCreateInfo p{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        p.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        p.queueFamilyIndex = ctx.queueFamily();
        VkCommandPool handle;
        gpu::check(vkCreateCommandPool(ctx.device(), &p, nullptr, &handle), "vkCreateCommandPool");
        pool = gpu::Unique<VkCommandPool>(ctx.device(), handle, vkDestroyCommandPool);
        VkCommandBufferAllocateInfo a{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        a.commandPool = pool;
        a.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        a.commandBufferCount = 1;
        gpu::check(vkAllocateCommandBuffers(ctx.device(), &a, &cmd), "vkAllocateCommandBuffers");
        VkFenceCreateInfo f{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence fh;
        gpu::check(vkCreateFence(ctx.device(), &f, nullptr, &fh), "vkCreateFence");
        fence = gpu::Unique<VkFence>(ctx.device(), fh, vkDestroyFence);
    }

    std::map<std::string, AovSource> aovSources(const render::GBuffer& g, TextureHandle lit, TextureHandle color) {
        return {
            {"linear", {lit, 3}},           {"color", {color, 3}},
            {"depth", {g.depth, 1, 0}}, {"normal", {g.normal, 3}},
            {"roughness", {g.normal, 1, 3}}, {"motion", {g.motion, 2}},
        };
    }

    void addReadback(FrameGraph& fg, const std::map<std::string, AovSource>& sources,
                     const std::vector<std::string>& aovs);
    FrameResult collect(const FrameGraph& fg, const std::map<std::string, AovSource>& sources,
                        const std::vector<std::string>& aovs);
};

void FrameRunner::Impl::addReadback(FrameGraph& fg, const std::map<std::string, AovSource>& sources,
                                    const std::vector<std::string>& aovs) {
    struct Data {
        std::vector<std::pair<std::string, TextureHandle>> reads;
    };
    fg.addPass<Data>(
        "capture.readback", PassType::Transfer,
        [&](PassBuilder& b, Data& d) {
            for (const std::string& name : aovs) {
                TextureHandle h = sources.at(name).texture;
                // Two AOVs may read the same texture (normal, roughness): one copy is enough.
                bool seen = std::any_of(d.reads.begin(), d.reads.end(), [&](auto& r) { return r.second == h; });
                b.read(h, TextureUsage::TransferSrc);
                if (!seen) d.reads.emplace_back(name, h);
            }
            b.sideEffect();
        },
        [this](const Data& d, PassContext& pc) {
            for (const auto& [name, h] : d.reads) {
                const TextureInfo& info = pc.info(h);
                VkDeviceSize bytes = VkDeviceSize(info.desc.width) * info.desc.height * gpu::bytesPerPixel(info.desc.format);
                auto it = readback.find(info.name);
                if (it == readback.end() || it->second.size() != bytes)
                    it = readback.insert_or_assign(info.name, gpu::Buffer(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                                                          true, "capture.readback." + info.name))
                             .first;
                VkBufferImageCopy copy{};
                copy.imageSubresource = {aspectOf(info.desc.format), 0, 0, 1};
                copy.imageExtent = {info.desc.width, info.desc.height, 1};
                vkCmdCopyImageToBuffer(pc.cmd(), pc.image(h), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, it->second.get(), 1,
                                       &copy);
            }
        });
}

FrameResult FrameRunner::Impl::collect(const FrameGraph& fg, const std::map<std::string, AovSource>& sources,
                                       const std::vector<std::string>& aovs) {
    FrameResult result;
    for (const std::string& name : aovs) {
        const AovSource& src = sources.at(name);
        const TextureInfo& info = fg.texture(src.texture.id);
        const gpu::Buffer& buf = readback.at(info.name);
        size_t n = size_t(info.desc.width) * info.desc.height;
        std::vector<float> rgba = gpu::decodeRGBA(info.desc.format, buf.mapped(), n);
        AovImage img{info.desc.width, info.desc.height, src.channels, {}};
        if (src.sourceChannel >= 0) {
            img.rgba.assign(n * 4, 0.0f);
            for (size_t i = 0; i < n; ++i) {
                float v = rgba[i * 4 + size_t(src.sourceChannel)];
                img.rgba[i * 4 + 0] = img.rgba[i * 4 + 1] = img.rgba[i * 4 + 2] = v;
                img.rgba[i * 4 + 3] = 1.0f;
            }
        } else {
            img.rgba = std::move(rgba);
        }
        result.aovs.emplace(name, std::move(img));
    }
    for (const auto& t : executor.readTimings()) {
        result.passes.push_back({t.name, t.ms});
        if (t.name.rfind("capture.", 0) != 0) result.frameMs += t.ms;
    }
    result.memory = fg.compiled().memory;
    return result;
}

FrameRunner::FrameRunner(const gpu::Context& ctx, render::Renderer& renderer, uint32_t width, uint32_t height)
    : impl_(std::make_unique<Impl>(ctx, renderer, width, height)) {}
FrameRunner::~FrameRunner() = default;

void FrameRunner::resize(uint32_t width, uint32_t height) {
    impl_->width = width;
    impl_->height = height;
}

FrameResult FrameRunner::render(const render::FrameInputs& frame, const std::vector<std::string>& aovs,
                                const LitHook& litHook, const PresentHook& presentHook, VkSemaphore wait,
                                VkSemaphore signal) {
    Impl& m = *impl_;
    auto known = [](const std::vector<std::string>& list, const std::string& a) {
        return std::find(list.begin(), list.end(), a) != list.end();
    };
    ModuleAovs moduleRequest;
    for (const std::string& a : aovs) {
        if (aovProvider(litHook.modules, a)) moduleRequest.requested.push_back(a);
        else if (!known(availableAovs(), a)) throw argumentError("unknown AOV '" + a + "'");
    }
    auto fg = std::make_unique<FrameGraph>(FrameGraphConfig{m.width, m.height});
    render::GBuffer g = m.renderer.addGBufferPasses(*fg, frame);
    TextureHandle lit = m.renderer.addLightingPass(*fg, frame, g, {.moduleSpecular = litHook.moduleSpecular});
    if (litHook) lit = litHook.addPasses(*fg, g, lit, moduleRequest);
    TextureHandle color = m.renderer.addTonemapPass(*fg, lit);
    // The frame's image is its output even when nobody reads it back (warm-up, timing runs).
    fg->markOutput(color);
    if (presentHook) presentHook(*fg, color);
    auto sources = m.aovSources(g, lit, color);
    for (const std::string& a : moduleRequest.requested) {
        auto it = moduleRequest.provided.find(a);
        if (it == moduleRequest.provided.end()) {
            const ModuleInfo& module = *aovProvider(litHook.modules, a);
            // Off, or on with nothing for the AOV to show (the cmo AOV of a scene without CMOs).
            throw argumentError("AOV '" + a + "' comes from the " + module.name + " module, which does not make it " +
                                "this frame: the module is off" +
                                (module.enableSetting.empty() ? "" : " (" + module.enableSetting + "=false)") +
                                " or the scene has nothing that AOV shows");
        }
        sources[a] = it->second;
    }
    if (!aovs.empty()) m.addReadback(*fg, sources, aovs);
    fg->compile(m.allocator);

    gpu::check(vkResetCommandBuffer(m.cmd, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vkBeginCommandBuffer(m.cmd, &begin);
    fg->execute(m.executor, m.cmd);
    gpu::check(vkEndCommandBuffer(m.cmd), "vkEndCommandBuffer");

    VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &m.cmd;
    if (wait) {
        submit.waitSemaphoreCount = 1;
        submit.pWaitSemaphores = &wait;
        submit.pWaitDstStageMask = &waitStage;
    }
    if (signal) {
        submit.signalSemaphoreCount = 1;
        submit.pSignalSemaphores = &signal;
    }
    VkFence fence = m.fence;
    gpu::check(vkResetFences(m.ctx.device(), 1, &fence), "vkResetFences");
    gpu::check(vkQueueSubmit(m.ctx.queue(), 1, &submit, fence), "vkQueueSubmit");
    gpu::check(vkWaitForFences(m.ctx.device(), 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
    FrameResult result = m.collect(*fg, sources, aovs);
    m.lastGraph = std::move(fg);
    return result;
}

std::string FrameRunner::graphDot() const { return impl_->lastGraph ? impl_->lastGraph->dumpDot() : ""; }
nlohmann::json FrameRunner::graphJson() const {
    return impl_->lastGraph ? impl_->lastGraph->dumpJson() : nlohmann::json();
}

}  // namespace speculum::app
