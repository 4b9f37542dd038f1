// --script FILE: a JSON list of actions the editor replays one after the other, so that a test
// can drive it under Xvfb exactly as a user would. Input actions (click, drag, hover, key) are
// injected into ImGui's input for the frames they last, so they go through the same code as
// the mouse and the keyboard; the others call what the UI's buttons call.
//
//   [{"click": [640, 360]}, {"key": "ctrl+z"}, {"drag": {"from": [600, 300], "to": [650, 300], "frames": 6}},
//    {"set": "reflections.max_steps", "value": 64}, {"material": "chrome", "field": "material.roughness", "value":
//    0.3},
//    {"click_node": "chrome_sphere"}, {"drag_gizmo": {"axis": 0, "pixels": 60}},
//    {"action": "add_probe"}, {"screenshot": "out/view.png"}, {"save_as": "out/scene.gltf"}, {"action": "quit"}]
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

struct ImGuiIO;

namespace speculum::editor {

class Script {
public:
    // Throws Error(BadInput) naming the file and the action for unreadable JSON or an unknown
    // action, before any window opens.
    static Script load(const std::filesystem::path& file);
    Script() = default;
    bool active() const { return !actions_.is_null(); }
    bool finished() const { return active() && index_ >= actions_.size(); }

    // Once per frame, between the backends' new frame and ImGui::NewFrame(): sets the mouse and
    // the keys this frame's part of the current action asks for. Returns the action when it is a
    // command for the editor to carry out this frame (once), or null.
    const nlohmann::json* step(ImGuiIO& io);
    const std::string& file() const { return file_; }
    // The command just returned becomes `action` (an input action the editor worked out, such
    // as a click at the pixel where a node is), replayed from its first frame.
    void replaceCurrent(nlohmann::json action) {
        actions_[index_] = std::move(action);
        frame_ = 0;
        hold_ = 0;
    }
    // The command just returned lasts `frames` more frames (a measurement) before the next.
    void hold(int frames) { hold_ = frames; }

private:
    std::string file_;
    nlohmann::json actions_;
    size_t index_ = 0;
    int frame_ = 0;  // frames spent on the current action
    int hold_ = 0;
    float mouseX_ = -1.0f, mouseY_ = -1.0f;
};

}  // namespace speculum::editor
