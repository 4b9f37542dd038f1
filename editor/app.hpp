// The editor's window: the document, the viewport, the ImGui panels (panels.cpp), the camera,
// picking, the translate gizmo and the overlays (gizmo.cpp), and the --script driver.
#pragma once

#include "camera.hpp"
#include "document.hpp"
#include "script.hpp"
#include "panel_cache.hpp"
#include "viewport.hpp"

#include "speculum/app/window.hpp"
#include "speculum/gpu/resources.hpp"

#include <array>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace speculum::editor {

struct Options {
    std::filesystem::path scene;
    std::filesystem::path script;
    std::string device;
    uint32_t width = 1280, height = 720;
    std::string recover = "ask";  // ask, yes, no: a newer autosave found on start
};

// Runs the editor; returns the exit status.
int run(const Options& options);

// Where the viewport sits in the window, in window pixels.
struct Rect {
    float x = 0, y = 0, w = 1, h = 1;
    bool contains(float px, float py) const { return px >= x && py >= y && px < x + w && py < y + h; }
};

// The translate gizmo's drag: which handle, and where it started.
struct GizmoDrag {
    // 0 x, 1 y, 2 z, 3 the xz plane (translate); 4, 5, 6 the box's x, y, z extents; 7 the blend
    // distance; -1 none.
    int axis = -1;
    glm::vec3 start{0.0f};
    glm::vec3 current{0.0f};
    glm::vec3 sent{0.0f};   // the position the probes module last re-bakes from (live re-bake)
    float mouseX = 0, mouseY = 0;
    ReflectionProbe probe;  // extents and blend handles: the previewed probe
};

class EditorApp {
public:
    EditorApp(const Options& options, Document document);
    ~EditorApp();
    // Returns the exit status.
    int loop();

    // What the UI and the script both call.
    void addProbeAtPick(ProbeKind kind = ProbeKind::LocalCubemap);
    // A planar probe on the picked surface's plane, spanning the picked object's bounds there.
    void addPlanarAtPick();
    void deleteSelectedProbe();
    void save();
    void saveAs(const std::filesystem::path& path);
    void undo();
    void redo();
    void select(int node);
    void frameSelection();
    void setSettingValue(const std::string& name, double value);
    void setDebugView(const std::string& name, double value);
    void setMaterialValue(int material, const std::string& field, double value);
    void setProbeValue(int node, const std::string& field, double value);

private:
    // panels.cpp
    void drawMenuBar();
    void drawOutliner();
    void drawInspector();
    void drawSettings();
    void drawFrameGraph();
    void drawRecoverPopup();
    // gizmo.cpp
    bool gizmoInput(const render::CameraState& cam);
    void drawOverlays(const render::CameraState& cam);
    bool project(const render::CameraState& cam, glm::vec3 world, float& x, float& y) const;
    // Where a probe's shape handles are (extents on +x, +y, +z; blend on +x inside), in world space.
    glm::vec3 handlePosition(const glm::mat4& world, const ReflectionProbe& probe, int handle) const;
    bool shapeDrag(const render::CameraState& cam, const Node& node, float mouseX, float mouseY);
    int hitHandle(const render::CameraState& cam, glm::vec3 origin, float len, const glm::mat4& world,
                  const ReflectionProbe& probe) const;
    // app.cpp
    void layout();
    void viewportInput(float dt);
    void shortcuts();
    void runScriptAction(const nlohmann::json& action);
    void scriptClickNode(const std::string& name);
    void scriptDragGizmo(const nlohmann::json& drag);
    void scriptFail(const std::string& why);
    void renderFrame();
    void addPresentPasses(FrameGraph& graph, TextureHandle color, const gpu::Buffer* windowShot);
    void writeWindowShot(const gpu::Buffer& shot, VkExtent2D extent);
    void updateTitle(double fps);
    void adaptInteractiveScale(double frameSeconds);
    void measureStep();
    void bakeWithProgress();

    Options options_;
    std::unique_ptr<app::Window> window_;
    std::unique_ptr<gpu::Context> ctx_;
    std::unique_ptr<app::Swapchain> swapchain_;
    Document doc_;
    std::unique_ptr<Viewport> viewport_;
    std::unique_ptr<ui::UiLayer> ui_;
    std::unique_ptr<PanelCache> panels_;  // over ui_: destroyed first
    Script script_;
    EditorCamera camera_;

    Rect view_;                // the viewport's rectangle in the window
    float scale_ = 1.0f;       // internal resolution / viewport size
    int interactiveStep_ = 4;  // index into the interactive scales (app.cpp): half scale
    int sinceScaleChange_ = 0;
    std::array<double, 5> recentFrames_{};  // seconds of the last interactive frames at this step
    bool interacting_ = false;     // camera or gizmo moved this frame
    std::chrono::steady_clock::time_point lastInteraction_{};
    int selectedNode_ = -1;
    std::optional<glm::ivec2> pendingPick_;
    bool pickAddsProbe_ = false;
    Pick pick_;  // the last pick (the point "add probe" uses)
    GizmoDrag drag_;
    bool pixelInspector_ = false;
    std::optional<glm::ivec2> inspectPixel_;
    std::string screenshotPath_;
    std::string windowShotPath_;
    std::string status_;
    bool quit_ = false;
    int exitCode_ = 0;
    std::optional<std::filesystem::path> recoverOffer_;
    char saveAsBuffer_[512] = {};
    std::optional<std::pair<int, Material>> materialBefore_;  // a material previewed during a drag
    std::map<std::string, double> editing_;                   // settings previewed during a drag: name -> value before
    nlohmann::json graph_;  // the frame graph of a recent frame (refreshed each second)
    std::vector<app::PassTime> passTimes_;
    double gpuMs_ = 0.0, uiMs_ = 0.0, uiCpuMs_ = 0.0;
    // What the frame-graph panel shows, refreshed once a second: numbers that change every frame
    // would redraw the cached panels every frame (panel_cache.hpp).
    std::vector<app::PassTime> shownPasses_;
    double shownGpuMs_ = 0.0, shownUiMs_ = 0.0;
    std::chrono::steady_clock::time_point shownAt_{};
    std::chrono::steady_clock::time_point lastAutosave_;
    // --script each_debug_view: one frame per view, with a viewport picture ("" none).
    struct DebugViewShot {
        std::string setting;
        double value = 0.0;
        std::string path;
    };
    std::vector<DebugViewShot> debugViewQueue_;
    // --script measure: frames left, and the counters.
    int measureLeft_ = 0;
    bool measureInteract_ = false;
    int measureTop_ = 6;
    bool measurePinned_ = false;  // the measurement holds the interactive scale it was given
    int measureFrames_ = 0;
    std::vector<double> measureUi_, measureWall_;  // per frame: UI ms (GPU + CPU), wall ms
    std::chrono::steady_clock::time_point measureLast_{};
    size_t measureCached_ = 0;
    std::chrono::steady_clock::time_point measureStart_;
};

}  // namespace speculum::editor
