// Dear ImGui (Debian's libimgui-dev 1.86: its GLFW and Vulkan backends) on the engine's window
// and swapchain, in frame-graph passes, so its GPU time shows beside the renderer's passes. The
// game's HUD and the editor share it; the pass is named by its caller (`game.hud`, `editor.ui`).
// The editor's panel cache (editor/panel_cache.hpp) draws with the same render pass and lists.
#pragma once

#include "speculum/framegraph.hpp"
#include "speculum/gpu/context.hpp"
#include "speculum/gpu/resources.hpp"

#include <functional>
#include <string>
#include <vector>

struct GLFWwindow;
struct ImDrawList;

namespace speculum::ui {

// The frame graph puts the image in COLOR_ATTACHMENT_OPTIMAL before a UI pass and moves it on
// after: the render pass loads (or clears), draws and leaves the layout alone. Passes that
// differ only in the load op are compatible, so ImGui's one pipeline draws in both.
gpu::Unique<VkRenderPass> makeRenderPass(VkDevice dev, VkFormat format, VkAttachmentLoadOp load);
gpu::Unique<VkFramebuffer> makeFramebuffer(VkDevice dev, VkRenderPass pass, VkImageView view, VkExtent2D e);
// ImGui's draw data restricted to `lists` (in its order), drawn inside `pass` on `fb` within
// `area` (what lavapipe rasterises), after `before` (when given) drew in the same pass.
void drawLists(VkCommandBuffer cmd, VkRenderPass pass, VkFramebuffer fb, VkRect2D area,
               const std::vector<ImDrawList*>& lists, const VkClearValue* clear,
               const std::function<void(VkCommandBuffer)>& before = {});
// Every list of this frame's ImGui::GetDrawData(), in order.
std::vector<ImDrawList*> allLists();

class UiLayer {
public:
    UiLayer(const gpu::Context& ctx, GLFWwindow* window, VkFormat format, uint32_t imageCount);
    ~UiLayer();
    UiLayer(const UiLayer&) = delete;
    UiLayer& operator=(const UiLayer&) = delete;

    // The backends' new frame (input from GLFW); the caller may then override ImGui's input
    // (the editor's --script driver does) before ImGui::NewFrame().
    void beginInput();
    // Adds pass `name`: all of ImGui::GetDrawData() over `target`, no cache (the game's HUD,
    // which changes every frame). Returns the handle it wrote.
    TextureHandle addPass(FrameGraph& graph, TextureHandle target, const std::string& name);
    // A framebuffer on `view` for renderPass(), kept until endFrame(): the swapchain view is the
    // frame graph's, so a framebuffer lives for one frame only (FrameRunner::render waits for
    // the frame before it returns).
    VkFramebuffer frameFramebuffer(VkImageView view, VkExtent2D e);
    // After the frame's submit finished: its framebuffers go.
    void endFrame();

    // The render pass ImGui's pipeline was made for (loads the target).
    VkRenderPass renderPass() const { return renderPass_; }
    VkFormat format() const { return format_; }
    const gpu::Context& context() const { return ctx_; }

private:
    const gpu::Context& ctx_;
    VkFormat format_;
    gpu::Unique<VkDescriptorPool> pool_;
    gpu::Unique<VkRenderPass> renderPass_;
    std::vector<gpu::Unique<VkFramebuffer>> framebuffers_;
    bool glfwInit_ = false;
    bool vulkanInit_ = false;
};

}  // namespace speculum::ui
