// Dear ImGui (Debian's libimgui-dev 1.86: its GLFW and Vulkan backends) on the engine's window
// and swapchain, in frame-graph passes, so their GPU time shows in the frame-graph panel beside
// the renderer's passes.
//
// The panels are cached. ImGui's draw of the whole 1280x720 window cost 8-12 ms on lavapipe, 12-16%
// of an interactive frame (the viewport shrinks while the camera moves; the panels do not). But
// the panels rarely change while the camera moves: their draw lists (vertices, indices, commands)
// are hashed each frame and drawn into a window-sized cache image only when the hash changes
// (`editor.ui_panels`); every frame copies the cache into the swapchain image (`editor.ui_copy`),
// and `editor.ui` draws the viewport's image into its rectangle and then what lies over it: the
// background list (the gizmo and probe overlays) and any window that reaches into the viewport's
// rectangle (menus, popups, tooltips), in ImGui's order. On lavapipe a render pass costs by its
// area (the overlays' few hundred vertices over the 660x511 viewport: 3.5 ms; an 8x8 area: 0.4
// ms), so the pass covers only the viewport and the live lists, and the viewport's image is drawn
// in it rather than blitted in a pass of its own (another 3 ms).
#pragma once

#include "speculum/framegraph.hpp"
#include "speculum/gpu/context.hpp"
#include "speculum/gpu/pipeline.hpp"
#include "speculum/gpu/resources.hpp"

#include <vector>

struct GLFWwindow;
struct ImDrawList;

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
    // Adds `editor.ui`: all of ImGui::GetDrawData() over `target`, no cache (the game's HUD,
    // which changes every frame). Returns the handle it wrote.
    TextureHandle addPass(FrameGraph& graph, TextureHandle target);
    // Splits ImGui::GetDrawData() into the cached panels and the lists drawn each frame (those
    // that reach into `viewport`, x y w h in window pixels), then adds `editor.ui_panels` when the
    // panels changed and `editor.ui_copy`: the panels over grey into `target` (the swapchain
    // image, whole, of size `extent`). Returns the handle it wrote.
    TextureHandle addPanels(FrameGraph& graph, TextureHandle target, VkExtent2D extent, const float viewport[4]);
    // Adds `editor.ui`: `view` (the viewport's image) scaled into `viewport` (x y w h in window
    // pixels, whole pixels), then the lists over the viewport, drawn over `target`.
    TextureHandle addOverlays(FrameGraph& graph, TextureHandle target, TextureHandle view, const float viewport[4]);
    // Frames whose panels came from the cache (the measurement prints them).
    size_t cachedFrames() const { return cachedFrames_; }
    // After the frame's submit finished: its framebuffers go.
    void endFrame();

private:
    const gpu::Context& ctx_;
    gpu::Unique<VkDescriptorPool> pool_;
    gpu::Unique<VkRenderPass> renderPass_;  // loads the target (editor.ui)
    gpu::Unique<VkRenderPass> clearPass_;   // clears the cache to the window's grey (compatible)
    gpu::Image cache_;                      // the panels, window-sized, TRANSFER_SRC between frames
    gpu::Pipeline viewportPipeline_;        // editor/viewport.frag inside renderPass_
    gpu::Unique<VkSampler> linear_;
    gpu::Unique<VkFramebuffer> cacheFramebuffer_;
    VkFormat format_;
    uint64_t cacheHash_ = 0;
    bool cacheValid_ = false;
    std::vector<ImDrawList*> panels_, live_;  // this frame's split of ImGui's draw lists
    float liveArea_[4] = {};                  // x0 y0 x1 y1: the live lists' clip rectangles
    size_t cachedFrames_ = 0;
    // One per recorded frame: the swapchain view is the frame graph's, so a framebuffer lives for
    // one frame only (FrameRunner::render waits for the frame before it returns).
    std::vector<gpu::Unique<VkFramebuffer>> framebuffers_;
    bool glfwInit_ = false;
    bool vulkanInit_ = false;
};

}  // namespace speculum::editor
