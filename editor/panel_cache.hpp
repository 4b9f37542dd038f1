// The editor's panels, cached over speculum::ui::UiLayer (engine/ui). ImGui's draw of the whole 1280x720 window cost 8-12 ms on lavapipe, 12-16%
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
#include "speculum/gpu/pipeline.hpp"
#include "speculum/gpu/resources.hpp"
#include "speculum/ui/ui_layer.hpp"

#include <vector>

struct ImDrawList;

namespace speculum::editor {

class PanelCache {
public:
    explicit PanelCache(ui::UiLayer& ui);
    ~PanelCache();
    PanelCache(const PanelCache&) = delete;
    PanelCache& operator=(const PanelCache&) = delete;

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

private:
    ui::UiLayer& ui_;
    const gpu::Context& ctx_;
    gpu::Unique<VkRenderPass> clearPass_;   // clears the cache to the window's grey (compatible)
    gpu::Image cache_;                      // the panels, window-sized, TRANSFER_SRC between frames
    gpu::Pipeline viewportPipeline_;        // editor/shaders/viewport.frag inside the UI's render pass
    gpu::Unique<VkSampler> linear_;
    gpu::Unique<VkFramebuffer> cacheFramebuffer_;
    uint64_t cacheHash_ = 0;
    bool cacheValid_ = false;
    std::vector<ImDrawList*> panels_, live_;  // this frame's split of ImGui's draw lists
    float liveArea_[4] = {};                  // x0 y0 x1 y1: the live lists' clip rectangles
    size_t cachedFrames_ = 0;
};

}  // namespace speculum::editor
