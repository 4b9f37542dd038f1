#include "panel_cache.hpp"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

namespace speculum::editor {

namespace {

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

PanelCache::PanelCache(ui::UiLayer& ui)
    : ui_(ui), ctx_(ui.context()), clearPass_(ui::makeRenderPass(ui.context().device(), ui.format(), VK_ATTACHMENT_LOAD_OP_CLEAR)) {
    gpu::GraphicsPipelineDesc vp;
    vp.vertexShader = "engine/fullscreen.vert";
    vp.fragmentShader = "editor/viewport.frag";
    vp.pushConstantBytes = sizeof(float) * 4;
    vp.colorFormats = {ui.format()};
    vp.depthTest = vp.depthWrite = false;
    vp.cull = VK_CULL_MODE_NONE;
    vp.vertexInput = false;
    vp.name = "editor.ui.viewport";
    vp.renderPass = ui.renderPass();
    viewportPipeline_ = gpu::createGraphicsPipeline(ctx_, vp);
    linear_ = gpu::createSampler(ctx_, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, false);
}

PanelCache::~PanelCache() {
    vkDeviceWaitIdle(ctx_.device());
}

TextureHandle PanelCache::addPanels(FrameGraph& graph, TextureHandle target, VkExtent2D e, const float viewport[4]) {
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
        cache_ = gpu::Image(ctx_, {e.width, e.height, ui_.format(), 1, 1, false,
                                   VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT},
                            "editor.ui_cache");
        cacheFramebuffer_ = ui::makeFramebuffer(ctx_.device(), clearPass_, cache_.view(), e);
        cacheValid_ = false;
    }
    const bool redraw = !cacheValid_ || hash != cacheHash_;
    if (!redraw) ++cachedFrames_;
    TextureHandle cache = graph.importTexture(
        "editor.ui_cache", {.width = e.width, .height = e.height, .format = ui_.format()},
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
                             ui::drawLists(pc.cmd(), clearPass_, cacheFramebuffer_, {{0, 0}, e}, panels_, &grey);
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

TextureHandle PanelCache::addOverlays(FrameGraph& graph, TextureHandle target, TextureHandle view,
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
            VkFramebuffer fb = ui_.frameFramebuffer(pc.view(data.target), e);
            // The area: the viewport and the live lists' clip rectangles, within the window.
            float x0 = std::min(rect[0], liveArea_[0]), y0 = std::min(rect[1], liveArea_[1]);
            float x1 = std::max(rect[0] + rect[2], liveArea_[2]), y1 = std::max(rect[1] + rect[3], liveArea_[3]);
            int32_t ax = std::clamp(int32_t(std::floor(x0)), 0, int32_t(e.width) - 1);
            int32_t ay = std::clamp(int32_t(std::floor(y0)), 0, int32_t(e.height) - 1);
            VkRect2D area{{ax, ay},
                          {uint32_t(std::clamp(int32_t(std::ceil(x1)), ax + 1, int32_t(e.width)) - ax),
                           uint32_t(std::clamp(int32_t(std::ceil(y1)), ay + 1, int32_t(e.height)) - ay)}};
            ui::drawLists(pc.cmd(), ui_.renderPass(), fb, area, live_, nullptr, [&](VkCommandBuffer cmd) {
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

}  // namespace speculum::editor
