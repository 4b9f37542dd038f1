// The editor's document (docs/design.md section 9, the editor): the glTF scene and the settings, changed only
// through commands on one stack, so that every edit can be undone and the ImGui panels and the
// --script driver make exactly the same edits. Pure C++: no window, no device (tested by
// editor/tests/document_test.cpp).
#pragma once

#include "speculum/scene.hpp"
#include "speculum/settings.hpp"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace speculum::editor {

class Document;

// One undoable edit. `apply` and `revert` are exact inverses; both leave node.world consistent.
struct Command {
    std::string name;  // "move probe", for the Edit menu and the log
    std::function<void(Document&)> apply;
    std::function<void(Document&)> revert;
    // What a command touches, so the viewport rebuilds only what changed.
    enum class Touches : uint8_t { Materials, Probes, Settings } touches = Touches::Settings;
};

// Command factories: each captures the before and after values it needs.
Command addProbe(const Document& doc, const std::string& name, glm::vec3 position, const ReflectionProbe& probe,
                 glm::quat rotation = glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
Command moveNode(const Document& doc, int node, glm::vec3 translation);
Command setProbe(const Document& doc, int node, const ReflectionProbe& probe);  // resize, shape, ...
Command deleteProbe(const Document& doc, int node);
Command setMaterial(const Document& doc, int material, const Material& value);
Command setSetting(const Document& doc, const std::string& name, double value);

class Document {
public:
    Document(Scene scene, std::vector<SettingDesc> settingsTable);
    // Loads the scene (loadScene's errors pass through: exit 3 with its message) and, when it is
    // there, the settings file saved beside it (settingsPathFor).
    static Document open(const std::filesystem::path& path, std::vector<SettingDesc> settingsTable);

    const Scene& scene() const { return scene_; }
    Scene& mutableScene() { return scene_; }  // commands only
    const Settings& settings() const { return settings_; }
    Settings& mutableSettings() { return settings_; }  // commands only
    const std::filesystem::path& path() const { return scene_.path; }

    // Applies and pushes; clears the redo side.
    void execute(Command command);
    bool undo();
    bool redo();
    bool canUndo() const { return !undo_.empty(); }
    bool canRedo() const { return !redo_.empty(); }
    const std::string& undoName() const;
    const std::string& redoName() const;
    // Bumped by every execute, undo and redo: the viewport compares it to know what to rebuild.
    uint64_t revision() const { return revision_; }
    // What the commands executed, undone or redone since the last call touched (a bit per
    // Command::Touches value); clears it.
    uint32_t takeTouched() {
        uint32_t t = touched_;
        touched_ = 0;
        return t;
    }
    static uint32_t bit(Command::Touches t) { return 1u << uint32_t(t); }
    // True when the scene differs from the last save (or load): undoing back to it is clean.
    bool dirty() const;

    // saveScene (temporary file, then rename) and the settings beside it; the document becomes
    // clean. Throws speculum::Error with saveScene's message; the document is unchanged then.
    void save();
    void saveAs(const std::filesystem::path& path);
    // Writes the side file (autosavePath) when there are unsaved edits since the last autosave.
    // Returns true when it wrote.
    bool autosave();
    std::filesystem::path autosavePath() const { return autosavePathFor(scene_.path); }
    static std::filesystem::path autosavePathFor(const std::filesystem::path& scene);
    static std::filesystem::path settingsPathFor(const std::filesystem::path& scene);
    // An autosave beside `scene` that is newer than it, if any (offered on start).
    static std::optional<std::filesystem::path> newerAutosave(const std::filesystem::path& scene);
    // Replaces the scene with the autosave's content, keeping the scene's own path, as one
    // dirty state (saving writes it over the original only when the user saves).
    void recoverFrom(const std::filesystem::path& autosave);

    // Index of the first node that the document on disk did not have (editor-added nodes).
    size_t savedNodeCount() const;

private:
    struct Entry {
        Command command;
        uint64_t id;
    };
    uint64_t topId() const { return undo_.empty() ? 0 : undo_.back().id; }
    Scene scene_;
    Settings settings_;
    std::vector<Entry> undo_;
    std::vector<Entry> redo_;
    bool step(std::vector<Entry>& from, std::vector<Entry>& to, bool apply);
    uint64_t nextId_ = 1;
    uint64_t savedId_ = 0;
    bool recovered_ = false;  // dirty regardless of the stack until saved
    uint64_t autosavedRevision_ = 0;
    uint64_t revision_ = 0;
    uint32_t touched_ = 0;
};

// The node's world from its parent's and its TRS (or matrix); updates its descendants too.
void updateWorld(Scene& scene, int node);
// Field by field (nodes' TRS, probes, materials' factors and SPECULUM_reflections), with the
// first difference in `why`: the undo/redo and save/load tests compare with it.
bool sameContent(const Scene& a, const Scene& b, std::string* why = nullptr);

}  // namespace speculum::editor
