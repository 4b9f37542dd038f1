#include "script.hpp"

#include "speculum/core.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

namespace speculum::editor {

namespace {

const std::set<std::string>& knownKeys() {
    // clang-format off
    static const std::set<std::string> keys = {
        "click", "drag", "hover", "key", "wait", "set", "material", "probe", "action", "select", "camera",
        "screenshot", "save_as", "debug_view", "expect_selected", "measure", "click_node", "drag_gizmo",
        "window_screenshot", "each_debug_view"};
    // clang-format on
    return keys;
}

int glfwKey(const std::string& name) {
    if (name.size() == 1 && name[0] >= 'a' && name[0] <= 'z') return GLFW_KEY_A + (name[0] - 'a');
    if (name == "delete") return GLFW_KEY_DELETE;
    if (name == "escape") return GLFW_KEY_ESCAPE;
    return -1;
}

// "ctrl+shift+z" -> key and modifiers.
struct Chord {
    int key = -1;
    bool ctrl = false, shift = false;
};
Chord parseChord(const std::string& text) {
    Chord c;
    std::stringstream ss(text);
    std::string part;
    while (std::getline(ss, part, '+')) {
        if (part == "ctrl")
            c.ctrl = true;
        else if (part == "shift")
            c.shift = true;
        else
            c.key = glfwKey(part);
    }
    return c;
}

[[noreturn]] void bad(const std::string& file, size_t i, const std::string& problem) {
    throw inputError(file, "action " + std::to_string(i) + ": " + problem);
}

void checkPoint(const nlohmann::json& p, const std::string& file, size_t i, const char* what) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
        bad(file, i, std::string(what) + " needs [x, y] in window pixels");
}

void validate(const nlohmann::json& a, const std::string& file, size_t i) {
    if (!a.is_object() || a.size() < 1) bad(file, i, "must be an object such as {\"click\": [x, y]}");
    const std::string key = a.begin().key();
    std::string found;
    for (auto it = a.begin(); it != a.end(); ++it)
        if (knownKeys().count(it.key())) found = it.key();
    if (found.empty()) bad(file, i, "unknown action \"" + key + "\"");
    if (a.contains("click")) checkPoint(a["click"], file, i, "click");
    if (a.contains("hover")) checkPoint(a["hover"], file, i, "hover");
    if (a.contains("drag")) {
        const nlohmann::json& d = a["drag"];
        if (!d.is_object() || !d.contains("from") || !d.contains("to")) bad(file, i, "drag needs from and to");
        checkPoint(d["from"], file, i, "drag.from");
        checkPoint(d["to"], file, i, "drag.to");
    }
    if (a.contains("key") && (!a["key"].is_string() || parseChord(a["key"].get<std::string>()).key < 0))
        bad(file, i, "key needs a chord such as \"ctrl+z\" (a-z, delete, escape)");
    if ((a.contains("set") || a.contains("material") || a.contains("probe")) && !a.contains("value"))
        bad(file, i, "needs a \"value\"");
}

}  // namespace

Script Script::load(const std::filesystem::path& file) {
    Script s;
    s.file_ = file.string();
    std::ifstream in(file);
    if (!in || std::filesystem::is_directory(file)) throw inputError(s.file_, "cannot read the script");
    try {
        in >> s.actions_;
    } catch (const nlohmann::json::exception& e) {
        throw inputError(s.file_, std::string("not JSON: ") + e.what());
    }
    if (!s.actions_.is_array()) throw inputError(s.file_, "a script is a JSON list of actions");
    for (size_t i = 0; i < s.actions_.size(); ++i) validate(s.actions_[i], s.file_, i);
    return s;
}

const nlohmann::json* Script::step(ImGuiIO& io) {
    if (!active() || finished()) return nullptr;
    const nlohmann::json& a = actions_[index_];
    int f = frame_++;
    auto next = [&] {
        ++index_;
        frame_ = 0;
    };
    auto point = [](const nlohmann::json& p) { return ImVec2(p[0].get<float>(), p[1].get<float>()); };
    // The script owns the mouse while it runs: the real pointer does not move it.
    io.MousePos = ImVec2(mouseX_, mouseY_);
    io.MouseDown[0] = false;
    if (a.contains("click") || a.contains("hover")) {
        ImVec2 p = point(a.contains("click") ? a["click"] : a["hover"]);
        io.MousePos = p;
        mouseX_ = p.x;
        mouseY_ = p.y;
        io.MouseDown[0] = a.contains("click") && f == 0;
        // Press, release, then one more frame for the pick it started to come back.
        if (f >= (a.contains("click") ? 2 : 1)) next();
        return nullptr;
    }
    if (a.contains("drag")) {
        const nlohmann::json& d = a["drag"];
        int frames = std::max(1, d.value("frames", 6));
        ImVec2 from = point(d["from"]), to = point(d["to"]);
        float t = std::clamp(float(f) / float(frames), 0.0f, 1.0f);
        io.MousePos = ImVec2(from.x + (to.x - from.x) * t, from.y + (to.y - from.y) * t);
        io.MouseDown[0] = f <= frames;
        mouseX_ = io.MousePos.x;
        mouseY_ = io.MousePos.y;
        if (f > frames + 1) next();
        return nullptr;
    }
    if (a.contains("key")) {
        Chord c = parseChord(a["key"].get<std::string>());
        bool down = f == 0;
        io.KeysDown[c.key] = down;
        io.KeyCtrl = down && c.ctrl;
        io.KeyShift = down && c.shift;
        if (f >= 1) next();
        return nullptr;
    }
    if (a.contains("wait")) {
        if (f >= a["wait"].get<int>()) next();
        return nullptr;
    }
    // A command for the editor: carried out once, this frame; the next action waits one frame
    // so that its effect (a rebuild, a bake) is on screen first.
    if (f == 0) return &a;
    if (f <= hold_) return nullptr;
    hold_ = 0;
    next();
    return nullptr;
}

}  // namespace speculum::editor
