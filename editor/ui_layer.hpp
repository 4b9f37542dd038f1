// Dear ImGui (Debian's libimgui-dev 1.86: its GLFW and Vulkan backends) on the engine's window
// and swapchain. The UI is drawn by one frame-graph pass, `editor.ui`, after the viewport was
// blitted into the swapchain image, so its GPU time shows in the frame-graph panel beside the
// renderer's passes.
#pragma once

#include "speculum/framegraph.hpp"
#include "speculum/gpu/context.hpp"

#include <vector>

struct GLFWwindow;

namespace speculum::editor {

class UiLayer {
public:
    UiLayer(const gpu::Context& ctx, GLFWwindow* window, VkFormat format, uint32_t imageCount);
    ~UiLayer();
    UiLayer(const UiLayer&) = delete;
    UiLayer& operator=(const UiLayer&) = delete;

    // The backends' new frame (input from GLFW); the caller may then override ImGui's input
    // (the --script driver does) before ImGui::NewFrame().
    void beginInput();
    // Adds `editor.ui`: ImGui::GetDrawData() over `target` (a colour image the pass loads and
    // keeps); returns the handle it wrote.
    TextureHandle addPass(FrameGraph& graph, TextureHandle target);
    // After the frame's submit finished: its framebuffers go.
    void endFrame();

private:
    const gpu::Context& ctx_;
    gpu::Unique<VkDescriptorPool> pool_;
    gpu::Unique<VkRenderPass> renderPass_;
    // One per recorded frame: the swapchain view is the frame graph's, so a framebuffer lives for
    // one frame only (FrameRunner::render waits for the frame before it returns).
    std::vector<gpu::Unique<VkFramebuffer>> framebuffers_;
    bool glfwInit_ = false;
    bool vulkanInit_ = false;
};

}  // namespace speculum::editor
