#include "ui_layer.hpp"

#include "speculum/core.hpp"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

#include <algorithm>
#include <array>
#include <functional>
#include <cmath>
#include <limits>
#include <cstring>

namespace speculum::editor {

namespace {

void checkImgui(VkResult r) {
    if (r != VK_SUCCESS) gpu::check(r, "imgui vulkan backend");
}

// The frame graph puts the image in COLOR_ATTACHMENT_OPTIMAL before the pass and moves it on
// after: the render pass loads (or clears), draws and leaves the layout alone. Passes that
// differ only in the load op are compatible, so ImGui's one pipeline draws in both.
gpu::Unique<VkRenderPass> makeRenderPass(VkDevice dev, VkFormat format, VkAttachmentLoadOp load) {
    VkAttachmentDescription color{};
    color.format = format;
    color.samples = VK_SAMPLE_COUNT_1_BIT;
    color.loadOp = load;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    color.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    color.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &ref;
    VkRenderPassCreateInfo ri{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    ri.attachmentCount = 1;
    ri.pAttachments = &color;
    ri.subpassCount = 1;
    ri.pSubpasses = &sub;
    VkRenderPass rp;
    gpu::check(vkCreateRenderPass(dev, &ri, nullptr, &rp), "vkCreateRenderPass");
    return gpu::Unique<VkRenderPass>(dev, rp, vkDestroyRenderPass);
}

gpu::Unique<VkFramebuffer> makeFramebuffer(VkDevice dev, VkRenderPass pass, VkImageView view, VkExtent2D e) {
    VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fi.renderPass = pass;
    fi.attachmentCount = 1;
    fi.pAttachments = &view;
    fi.width = e.width;
    fi.height = e.height;
    fi.layers = 1;
    VkFramebuffer fb;
    gpu::check(vkCreateFramebuffer(dev, &fi, nullptr, &fb), "vkCreateFramebuffer");
    return gpu::Unique<VkFramebuffer>(dev, fb, vkDestroyFramebuffer);
}

// ImGui's draw data restricted to `lists` (in its order), drawn inside `pass` on `fb` within
// `area` (what lavapipe rasterises), after `before` (when given) drew in the same pass.
void drawLists(VkCommandBuffer cmd, VkRenderPass pass, VkFramebuffer fb, VkRect2D area,
               const std::vector<ImDrawList*>& lists, const VkClearValue* clear,
               const std::function<void(VkCommandBuffer)>& before = {}) {
    const ImDrawData* all = ImGui::GetDrawData();
    VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    bi.renderPass = pass;
    bi.framebuffer = fb;
    bi.renderArea = area;
    bi.clearValueCount = clear ? 1 : 0;
    bi.pClearValues = clear;
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    if (before) before(cmd);
    if (all && !lists.empty()) {
        ImDrawData part = *all;
        part.CmdLists = const_cast<ImDrawList**>(lists.data());
        part.CmdListsCount = int(lists.size());
        part.TotalVtxCount = part.TotalIdxCount = 0;
        for (const ImDrawList* l : lists) {
            part.TotalVtxCount += l->VtxBuffer.Size;
            part.TotalIdxCount += l->IdxBuffer.Size;
        }
        ImGui_ImplVulkan_RenderDrawData(&part, cmd);
    }
    vkCmdEndRenderPass(cmd);
}

// 64-bit multiply-xor hash, eight bytes a step (about 1 MB of panel vertices a frame).
uint64_t hashBytes(uint64_t h, const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i + 8 <= bytes; i += 8) {
        uint64_t w;
        std::memcpy(&w, p + i, 8);
        h = (h ^ w) * 0x100000001b3ull;
        h ^= h >> 29;
    }
    for (size_t i = bytes & ~size_t(7); i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    return h;
}

uint64_t hashList(uint64_t h, const ImDrawList* l) {
    h = hashBytes(h, l->VtxBuffer.Data, size_t(l->VtxBuffer.Size) * sizeof(ImDrawVert));
    h = hashBytes(h, l->IdxBuffer.Data, size_t(l->IdxBuffer.Size) * sizeof(ImDrawIdx));
    for (const ImDrawCmd& c : l->CmdBuffer) {
        h = hashBytes(h, &c.ClipRect, sizeof c.ClipRect);
        h = hashBytes(h, &c.TextureId, sizeof c.TextureId);
        uint32_t counts[3] = {c.ElemCount, c.IdxOffset, c.VtxOffset};
        h = hashBytes(h, counts, sizeof counts);
        h = hashBytes(h, &c.UserCallback, sizeof c.UserCallback);
    }
    return h;
}

}  // namespace

UiLayer::UiLayer(const gpu::Context& ctx, GLFWwindow* window, VkFormat format, uint32_t imageCount)
    : ctx_(ctx), format_(format) {
    VkDevice dev = ctx.device();
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16};
    VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pi.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    pi.maxSets = 16;
    pi.poolSizeCount = 1;
    pi.pPoolSizes = &size;
    VkDescriptorPool pool;
    gpu::check(vkCreateDescriptorPool(dev, &pi, nullptr, &pool), "vkCreateDescriptorPool");
    pool_ = gpu::Unique<VkDescriptorPool>(dev, pool, vkDestroyDescriptorPool);

    renderPass_ = makeRenderPass(dev, format, VK_ATTACHMENT_LOAD_OP_LOAD);
    clearPass_ = makeRenderPass(dev, format, VK_ATTACHMENT_LOAD_OP_CLEAR);
    gpu::GraphicsPipelineDesc vp;
    vp.vertexShader = "engine/fullscreen.vert";
    vp.fragmentShader = "editor/viewport.frag";
    vp.pushConstantBytes = sizeof(float) * 4;
    vp.colorFormats = {format};
    vp.depthTest = vp.depthWrite = false;
    vp.cull = VK_CULL_MODE_NONE;
    vp.vertexInput = false;
    vp.name = "editor.ui.viewport";
    vp.renderPass = renderPass_;
    viewportPipeline_ = gpu::createGraphicsPipeline(ctx, vp);
    linear_ = gpu::createSampler(ctx, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, false);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // the layout is the editor's, not a file's
    ImGui::StyleColorsDark();
    glfwInit_ = ImGui_ImplGlfw_InitForVulkan(window, true);
    if (!glfwInit_) throw Error(ExitCode::Failure, "ImGui's GLFW backend failed to start");
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = ctx.instance();
    info.PhysicalDevice = ctx.physicalDevice();
    info.Device = dev;
    info.QueueFamily = ctx.queueFamily();
    info.Queue = ctx.queue();
    info.DescriptorPool = pool_;
    info.MinImageCount = std::max(2u, imageCount);
    info.ImageCount = std::max(2u, imageCount);
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = checkImgui;
    vulkanInit_ = ImGui_ImplVulkan_Init(&info, renderPass_);
    if (!vulkanInit_) throw Error(ExitCode::Failure, "ImGui's Vulkan backend failed to start");
    ctx.submitAndWait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
}

UiLayer::~UiLayer() {
    vkDeviceWaitIdle(ctx_.device());
    framebuffers_.clear();
    cacheFramebuffer_ = {};
    if (vulkanInit_) ImGui_ImplVulkan_Shutdown();
    if (glfwInit_) ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

void UiLayer::beginInput() {
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
}

TextureHandle UiLayer::addPanels(FrameGraph& graph, TextureHandle target, VkExtent2D e, const float viewport[4]) {
    // The split: a list reaches over the viewport when its vertices, clipped by their command's
    // rectangle, cover more than a pixel of it in both directions (the fixed panels' borders touch its edges; a
    // window's clip rectangles alone are often the whole screen).
    panels_.clear();
    live_.clear();
    liveArea_[0] = liveArea_[1] = std::numeric_limits<float>::max();
    liveArea_[2] = liveArea_[3] = 0.0f;
    const ImDrawList* background = ImGui::GetBackgroundDrawList();
    const float vx0 = viewport[0], vy0 = viewport[1], vx1 = viewport[0] + viewport[2], vy1 = viewport[1] + viewport[3];
    uint64_t hash = 0xcbf29ce484222325ull ^ (uint64_t(e.width) << 32 | e.height);
    if (const ImDrawData* all = ImGui::GetDrawData())
        for (int i = 0; i < all->CmdListsCount; ++i) {
            ImDrawList* l = all->CmdLists[i];
            bool over = l == background;
            for (const ImDrawCmd& c : l->CmdBuffer) {
                if (over || c.UserCallback) break;
                ImVec2 lo(c.ClipRect.z, c.ClipRect.w), hi(c.ClipRect.x, c.ClipRect.y);
                for (unsigned k = c.IdxOffset; k < c.IdxOffset + c.ElemCount; ++k) {
                    const ImVec2& p = l->VtxBuffer[int(c.VtxOffset + l->IdxBuffer[int(k)])].pos;
                    lo = ImVec2(std::min(lo.x, p.x), std::min(lo.y, p.y));
                    hi = ImVec2(std::max(hi.x, p.x), std::max(hi.y, p.y));
                }
                lo = ImVec2(std::max({lo.x, c.ClipRect.x, vx0}), std::max({lo.y, c.ClipRect.y, vy0}));
                hi = ImVec2(std::min({hi.x, c.ClipRect.z, vx1}), std::min({hi.y, c.ClipRect.w, vy1}));
                over = hi.x - lo.x > 1.0f && hi.y - lo.y > 1.0f;
            }
            (over ? live_ : panels_).push_back(l);
            if (!over) hash = hashList(hash * 31 + uint64_t(i), l);
            if (!over) continue;
            for (const ImDrawCmd& c : l->CmdBuffer) {
                liveArea_[0] = std::min(liveArea_[0], std::max(c.ClipRect.x, 0.0f));
                liveArea_[1] = std::min(liveArea_[1], std::max(c.ClipRect.y, 0.0f));
                liveArea_[2] = std::max(liveArea_[2], std::min(c.ClipRect.z, float(e.width)));
                liveArea_[3] = std::max(liveArea_[3], std::min(c.ClipRect.w, float(e.height)));
            }
        }
    if (!cache_.get() || cache_.desc().width != e.width || cache_.desc().height != e.height) {
        vkDeviceWaitIdle(ctx_.device());
        cacheFramebuffer_ = {};
        cache_ = gpu::Image(ctx_, {e.width, e.height, format_, 1, 1, false,
                                   VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT},
                            "editor.ui_cache");
        cacheFramebuffer_ = makeFramebuffer(ctx_.device(), clearPass_, cache_.view(), e);
        cacheValid_ = false;
    }
    const bool redraw = !cacheValid_ || hash != cacheHash_;
    if (!redraw) ++cachedFrames_;
    TextureHandle cache = graph.importTexture(
        "editor.ui_cache", {.width = e.width, .height = e.height, .format = format_},
        {cache_.get(), cacheValid_ ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED,
         VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, cache_.desc().usage});
    cacheHash_ = hash;
    cacheValid_ = true;
    if (redraw) {
        struct Draw {
            TextureHandle cache;
        };
        cache = graph.addPass<Draw>(
                         "editor.ui_panels", PassType::Raster,
                         [&](PassBuilder& b, Draw& d) { d.cache = b.write(cache, TextureUsage::ColorAttachment); },
                         [this, e](const Draw&, PassContext& pc) {
                             // The window's grey, as the swapchain was cleared before the cache.
                             VkClearValue grey{};
                             grey.color = {{0.1f, 0.1f, 0.11f, 1.0f}};
                             drawLists(pc.cmd(), clearPass_, cacheFramebuffer_, {{0, 0}, e}, panels_, &grey);
                         })
                    .cache;
    }
    struct Copy {
        TextureHandle cache, target;
    };
    return graph
        .addPass<Copy>(
            "editor.ui_copy", PassType::Transfer,
            [&](PassBuilder& b, Copy& d) {
                d.cache = b.read(cache, TextureUsage::TransferSrc);
                d.target = b.write(target, TextureUsage::TransferDst);
            },
            [e](const Copy& d, PassContext& pc) {
                VkImageCopy region{};
                region.srcSubresource = region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                region.extent = {e.width, e.height, 1};
                vkCmdCopyImage(pc.cmd(), pc.image(d.cache), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pc.image(d.target),
                               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
            })
        .target;
}

TextureHandle UiLayer::addPass(FrameGraph& graph, TextureHandle target) {
    struct Data {
        TextureHandle target;
    };
    const Data& d = graph.addPass<Data>(
        "editor.ui", PassType::Raster,
        [&](PassBuilder& b, Data& data) {
            data.target = b.write(target, TextureUsage::ColorAttachment);
            b.sideEffect();
        },
        [this](const Data& data, PassContext& pc) {
            VkExtent2D e = pc.extent(data.target);
            framebuffers_.push_back(makeFramebuffer(ctx_.device(), renderPass_, pc.view(data.target), e));
            std::vector<ImDrawList*> all;
            if (const ImDrawData* draw = ImGui::GetDrawData())
                all.assign(draw->CmdLists, draw->CmdLists + draw->CmdListsCount);
            drawLists(pc.cmd(), renderPass_, framebuffers_.back(), {{0, 0}, e}, all, nullptr);
        });
    return d.target;
}

TextureHandle UiLayer::addOverlays(FrameGraph& graph, TextureHandle target, TextureHandle view,
                                   const float viewport[4]) {
    struct Data {
        TextureHandle target, view;
    };
    const std::array<float, 4> rect{viewport[0], viewport[1], viewport[2], viewport[3]};
    const Data& d = graph.addPass<Data>(
        "editor.ui", PassType::Raster,
        [&](PassBuilder& b, Data& data) {
            data.view = b.read(view, TextureUsage::Sampled);
            data.target = b.write(target, TextureUsage::ColorAttachment);
            b.sideEffect();
        },
        [this, rect](const Data& data, PassContext& pc) {
            VkExtent2D e = pc.extent(data.target);
            framebuffers_.push_back(makeFramebuffer(ctx_.device(), renderPass_, pc.view(data.target), e));
            // The area: the viewport and the live lists' clip rectangles, within the window.
            float x0 = std::min(rect[0], liveArea_[0]), y0 = std::min(rect[1], liveArea_[1]);
            float x1 = std::max(rect[0] + rect[2], liveArea_[2]), y1 = std::max(rect[1] + rect[3], liveArea_[3]);
            int32_t ax = std::clamp(int32_t(std::floor(x0)), 0, int32_t(e.width) - 1);
            int32_t ay = std::clamp(int32_t(std::floor(y0)), 0, int32_t(e.height) - 1);
            VkRect2D area{{ax, ay},
                          {uint32_t(std::clamp(int32_t(std::ceil(x1)), ax + 1, int32_t(e.width)) - ax),
                           uint32_t(std::clamp(int32_t(std::ceil(y1)), ay + 1, int32_t(e.height)) - ay)}};
            drawLists(pc.cmd(), renderPass_, framebuffers_.back(), area, live_, nullptr, [&](VkCommandBuffer cmd) {
                viewportPipeline_.bind(cmd);
                gpu::DescriptorWriter().sampled("image", pc.view(data.view), linear_).push(ctx_, cmd, viewportPipeline_);
                VkViewport v{rect[0], rect[1], rect[2], rect[3], 0.0f, 1.0f};
                VkRect2D scissor{{int32_t(rect[0]), int32_t(rect[1])}, {uint32_t(rect[2]), uint32_t(rect[3])}};
                vkCmdSetViewport(cmd, 0, 1, &v);
                vkCmdSetScissor(cmd, 0, 1, &scissor);
                vkCmdPushConstants(cmd, viewportPipeline_.layout(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                                   0, sizeof(float) * 4, rect.data());
                vkCmdDraw(cmd, 3, 1, 0, 0);
            });
        });
    return d.target;
}

void UiLayer::endFrame() {
    framebuffers_.clear();
}

}  // namespace speculum::editor
