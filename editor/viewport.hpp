// The viewport: a host of the same modules as speculum-capture (renderer, probes, reflections)
// over the document's scene. It rebuilds the GPU side when a command changed what the GPU holds
// (materials and probes are uploaded at construction), renders at an internal resolution the
// editor picks (reduced while the camera or a gizmo moves) and reads back a pick: the depth,
// normal and material index of one pixel, from the G-buffer.
#pragma once

#include "document.hpp"

#include "speculum/app/frame_runner.hpp"
#include "speculum/gpu/context.hpp"
#include "speculum/chain.hpp"
#include "speculum/render/renderer.hpp"

#include <nlohmann/json.hpp>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace speculum::editor {

struct Pick {
    bool hit = false;
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
    int material = -1;
    int node = -1;  // the instance's node whose surface is nearest the picked point
};

// A pixel's reflection diagnostics (the pixel inspector).
struct PixelInfo {
    bool valid = false;
    glm::vec3 method{0.0f};  // screen space, probes, sky weights
    float iterations = 0.0f;
    float roughness = 0.0f;
    glm::vec3 reflection{0.0f};  // pre-Fresnel radiance
};

// What the editor registers besides the modules: the `pick` AOV (G-buffer emissive.a, the
// material flags and index).
app::ModuleInfo editorModuleInfo();

class Viewport {
public:
    Viewport(const gpu::Context& ctx, Document& document);
    ~Viewport();

    // Rebuilds what the document's changes since the last call invalidated.
    void sync();
    // The scene's material factors changed outside a command (a slider being dragged): the
    // next frames draw them, without a rebuild or a bake.
    void previewMaterials() { renderer_->updateMaterialFactors(); }
    // Bakes what the probes ask for (every probe after a rebuild or requestBake).
    void updateProbes(const probes::Probes::Progress& progress);
    void requestBake(int probe) { chain_->probes().requestUpdate(probe); }
    // Live re-bake while a probe or CMO is dragged: the probes module captures it again from
    // `world`, a face per frame (Probes::moveProbe), before the drag's command rebuilds it.
    void moveProbeLive(int node, const glm::mat4& world) { chain_->probes().moveProbe(node, world); }
    const probes::Probes& probes() const { return chain_->probes(); }
    bool bakePending() const { return bakePending_; }

    struct FrameRequest {
        render::CameraState camera;
        bool cameraCut = false;
        std::optional<glm::ivec2> pick;     // internal-resolution pixel to pick
        std::optional<glm::ivec2> inspect;  // pixel for the pixel inspector
        bool screenshot = false;            // read back `color`
        // The camera or a gizmo moves: the low preset's reflections.* settings
        // (assets/settings/low.json) over the document's, as the game starts with (issue 23: the
        // module at about 0.6x the default chain's cost while nothing is still enough to judge).
        bool interactive = false;
    };
    app::FrameResult render(const FrameRequest& request, const app::PresentHook& present, VkSemaphore wait,
                            VkSemaphore signal);
    const Pick& lastPick() const { return pick_; }
    const PixelInfo& lastPixel() const { return pixel_; }
    // Frames rendered with this size and camera since the module was (re)built, this one
    // included: the reflections' colour history has seen that many frames (a capture with
    // --warmup steadyFrames()-1 --frames 1 renders the same image).
    int steadyFrames() const { return steadyFrames_; }
    std::string graphJson() const;
    const std::string& lastError() const { return error_; }

private:
    void rebuild();
    // The document's settings with the interactive overlay (FrameRequest::interactive).
    const Settings& interactiveSettings();
    Pick resolvePick(const app::FrameResult& frame, glm::ivec2 pixel, const render::CameraState& camera) const;
    const gpu::Context& ctx_;
    Document& doc_;
    uint64_t revision_ = 0;
    std::unique_ptr<render::Renderer> renderer_;
    std::unique_ptr<chain::Chain> chain_;  // probes, then reflections
    std::unique_ptr<app::FrameRunner> runner_;
    render::FrameInputs frame_;
    bool first_ = true;
    int steadyFrames_ = 0;
    bool bakePending_ = true;
    std::optional<Settings> interactive_;
    nlohmann::json interactiveOverlay_;  // low.json's reflections.* keys, read once
    Pick pick_;
    PixelInfo pixel_;
    std::string error_;
    uint32_t width_ = 1, height_ = 1;
    std::map<std::string, double> builtWith_;  // the settings the GPU side was built with
};

}  // namespace speculum::editor
