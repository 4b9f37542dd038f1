#include "document.hpp"

#include "speculum/core.hpp"

#include <algorithm>
#include <fstream>
#include <system_error>

namespace speculum::editor {

namespace {

size_t documentNodeCount(const Scene& scene) {
    const nlohmann::json& doc = scene.document;
    if (!doc.is_object() || !doc.contains("nodes") || !doc["nodes"].is_array()) return 0;
    return doc["nodes"].size();
}

void writeTextAtomically(const std::filesystem::path& path, const std::string& text) {
    std::filesystem::path tmp = path;
    tmp += ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw Error(ExitCode::Failure, path.string() + ": cannot save: cannot create " + tmp.string());
        out << text;
        if (!out.flush()) throw Error(ExitCode::Failure, path.string() + ": cannot save: write failed");
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw Error(ExitCode::Failure, path.string() + ": cannot save: " + ec.message());
}

}  // namespace

void updateWorld(Scene& scene, int node) {
    Node& n = scene.nodes.at(size_t(node));
    glm::mat4 parent = n.parent >= 0 ? scene.nodes[size_t(n.parent)].world : glm::mat4(1.0f);
    n.world = parent * localMatrix(n);
    for (int c : n.children) updateWorld(scene, c);
}

// ---- commands -----------------------------------------------------------------------------

Command addProbe(const Document& doc, const std::string& name, glm::vec3 position, const ReflectionProbe& probe,
                 glm::quat rotation) {
    (void)doc;
    Node node;
    node.name = name;
    node.translation = position;
    node.rotation = rotation;
    node.probe = probe;
    // A new root node at the end: undo in stack order always removes the last node again.
    return {"add probe",
            [node](Document& d) {
                Scene& s = d.mutableScene();
                s.nodes.push_back(node);
                int index = int(s.nodes.size() - 1);
                s.roots.push_back(index);
                updateWorld(s, index);
            },
            [](Document& d) {
                Scene& s = d.mutableScene();
                int index = int(s.nodes.size() - 1);
                s.roots.erase(std::remove(s.roots.begin(), s.roots.end(), index), s.roots.end());
                s.nodes.pop_back();
            },
            Command::Touches::Probes};
}

Command moveNode(const Document& doc, int node, glm::vec3 translation) {
    glm::vec3 before = doc.scene().nodes.at(size_t(node)).translation;
    auto set = [node](glm::vec3 t) {
        return [node, t](Document& d) {
            d.mutableScene().nodes[size_t(node)].translation = t;
            updateWorld(d.mutableScene(), node);
        };
    };
    bool probe = doc.scene().nodes[size_t(node)].probe.has_value();
    return {"move " + doc.scene().nodes[size_t(node)].name, set(translation), set(before),
            probe ? Command::Touches::Probes : Command::Touches::Materials};
}

Command setProbe(const Document& doc, int node, const ReflectionProbe& probe) {
    std::optional<ReflectionProbe> before = doc.scene().nodes.at(size_t(node)).probe;
    auto set = [node](std::optional<ReflectionProbe> p) {
        return [node, p](Document& d) { d.mutableScene().nodes[size_t(node)].probe = p; };
    };
    return {"edit probe " + doc.scene().nodes[size_t(node)].name, set(probe), set(before), Command::Touches::Probes};
}

Command deleteProbe(const Document& doc, int node) {
    const Scene& s = doc.scene();
    const Node& n = s.nodes.at(size_t(node));
    if (!n.probe) throw std::logic_error("deleteProbe: node " + std::to_string(node) + " has no probe");
    // saveScene keeps every node the file had, so only a node this session added (the last one,
    // with nothing else on it) goes away entirely; on any other node the probe extension does.
    bool removable = size_t(node) + 1 == s.nodes.size() && size_t(node) >= documentNodeCount(s) && n.mesh < 0 &&
                     n.camera < 0 && n.light < 0 && n.children.empty() && n.parent < 0;
    if (!removable) {
        Command c = setProbe(doc, node, ReflectionProbe{});
        c.name = "delete probe " + n.name;
        c.apply = [node](Document& d) { d.mutableScene().nodes[size_t(node)].probe.reset(); };
        return c;
    }
    Node saved = n;
    auto rootAt = std::find(s.roots.begin(), s.roots.end(), node) - s.roots.begin();
    return {"delete probe " + n.name,
            [node](Document& d) {
                Scene& sc = d.mutableScene();
                sc.roots.erase(std::remove(sc.roots.begin(), sc.roots.end(), node), sc.roots.end());
                sc.nodes.pop_back();
            },
            [saved, rootAt](Document& d) {
                Scene& sc = d.mutableScene();
                sc.nodes.push_back(saved);
                int index = int(sc.nodes.size() - 1);
                sc.roots.insert(sc.roots.begin() + std::min<ptrdiff_t>(rootAt, ptrdiff_t(sc.roots.size())), index);
                updateWorld(sc, index);
            },
            Command::Touches::Probes};
}

Command setMaterial(const Document& doc, int material, const Material& value) {
    Material before = doc.scene().materials.at(size_t(material));
    auto set = [material](Material m) {
        return [material, m](Document& d) { d.mutableScene().materials[size_t(material)] = m; };
    };
    return {"edit material " + before.name, set(value), set(before), Command::Touches::Materials};
}

Command setSetting(const Document& doc, const std::string& name, double value) {
    double before = doc.settings().get(name);
    auto set = [name](double v) { return [name, v](Document& d) { d.mutableSettings().set(name, v); }; };
    return {"set " + name, set(value), set(before), Command::Touches::Settings};
}

// ---- the document -------------------------------------------------------------------------

Document::Document(Scene scene, std::vector<SettingDesc> settingsTable)
    : scene_(std::move(scene)), settings_(std::move(settingsTable)) {}

Document Document::open(const std::filesystem::path& path, std::vector<SettingDesc> settingsTable) {
    Document doc(loadScene(path), std::move(settingsTable));
    std::filesystem::path settings = settingsPathFor(path);
    if (std::filesystem::is_regular_file(settings)) doc.settings_.load(settings);
    return doc;
}

void Document::execute(Command command) {
    command.apply(*this);
    touched_ |= bit(command.touches);
    undo_.push_back({std::move(command), nextId_++});
    redo_.clear();
    ++revision_;
}

// Undo and redo are one step: the newest entry of one stack reverted (undo) or applied (redo)
// and moved to the other.
bool Document::step(std::vector<Entry>& from, std::vector<Entry>& to, bool apply) {
    if (from.empty()) return false;
    Entry e = std::move(from.back());
    from.pop_back();
    if (apply)
        e.command.apply(*this);
    else
        e.command.revert(*this);
    touched_ |= bit(e.command.touches);
    to.push_back(std::move(e));
    ++revision_;
    return true;
}

bool Document::undo() {
    return step(undo_, redo_, false);
}

bool Document::redo() {
    return step(redo_, undo_, true);
}

const std::string& Document::undoName() const {
    static const std::string none;
    return undo_.empty() ? none : undo_.back().command.name;
}

const std::string& Document::redoName() const {
    static const std::string none;
    return redo_.empty() ? none : redo_.back().command.name;
}

bool Document::dirty() const {
    return recovered_ || topId() != savedId_;
}

size_t Document::savedNodeCount() const {
    return documentNodeCount(scene_);
}

void Document::save() {
    saveAs(scene_.path);
}

// The sky is named in scenes[].extras.environment relative to the scene's folder: a scene saved
// into another folder names it relative to that one. Returns the JSON value to restore.
static nlohmann::json* environmentEntry(nlohmann::json& doc) {
    if (!doc.is_object() || !doc.contains("scenes") || !doc["scenes"].is_array() || doc["scenes"].empty())
        return nullptr;
    size_t active = doc.contains("scene") && doc["scene"].is_number_unsigned() ? doc["scene"].get<size_t>() : 0;
    if (active >= doc["scenes"].size()) return nullptr;
    nlohmann::json& s = doc["scenes"][active];
    if (!s.is_object() || !s.contains("extras") || !s["extras"].is_object()) return nullptr;
    nlohmann::json& e = s["extras"];
    return e.contains("environment") && e["environment"].is_string() ? &e["environment"] : nullptr;
}

void Document::saveAs(const std::filesystem::path& path) {
    nlohmann::json* env = environmentEntry(scene_.document);
    std::optional<nlohmann::json> envBefore;
    if (env && std::filesystem::path(env->get<std::string>()).is_relative()) {
        std::error_code ec;
        std::filesystem::path from = std::filesystem::absolute(environmentPath(scene_), ec);
        std::filesystem::path folder = std::filesystem::absolute(path, ec).parent_path();
        std::filesystem::path rel = std::filesystem::relative(from, folder, ec);
        if (!ec && !rel.empty()) {
            envBefore = *env;
            *env = rel.generic_string();
        }
    }
    try {
        saveScene(scene_, path);  // throws with its message; nothing else changed yet
    } catch (...) {
        if (envBefore) *env = *envBefore;
        throw;
    }
    // Settings that differ from their defaults go beside the scene; the capture tool reads the
    // same file with --settings.
    nlohmann::json changed = nlohmann::json::object();
    nlohmann::json all = settings_.toJson();
    // Debug views (*.debug_*) are how the scene was looked at: a saved one would turn every
    // capture of the scene into that view.
    for (const SettingDesc& d : settings_.table())
        if (settings_.get(d.name) != d.defaultValue && all.contains(d.name) &&
            d.name.find(".debug_") == std::string::npos)
            changed[d.name] = all[d.name];
    std::filesystem::path settingsFile = settingsPathFor(path);
    if (!changed.empty())
        writeTextAtomically(settingsFile, changed.dump(2) + "\n");
    else
        std::filesystem::remove(settingsFile);
    scene_.path = path;
    savedId_ = topId();
    recovered_ = false;
    // An autosave older than the save is stale: it must not be offered on the next start.
    std::error_code ec;
    std::filesystem::remove(autosavePathFor(path), ec);
    autosavedRevision_ = revision_;
}

bool Document::autosave() {
    if (!dirty() || autosavedRevision_ == revision_) return false;
    saveScene(scene_, autosavePath());
    autosavedRevision_ = revision_;
    return true;
}

std::filesystem::path Document::autosavePathFor(const std::filesystem::path& scene) {
    return scene.parent_path() / (scene.stem().string() + ".autosave.glb");
}

std::filesystem::path Document::settingsPathFor(const std::filesystem::path& scene) {
    return scene.parent_path() / (scene.stem().string() + ".settings.json");
}

std::optional<std::filesystem::path> Document::newerAutosave(const std::filesystem::path& scene) {
    std::error_code ec;
    std::filesystem::path side = autosavePathFor(scene);
    if (!std::filesystem::is_regular_file(side, ec)) return std::nullopt;
    auto sideTime = std::filesystem::last_write_time(side, ec);
    if (ec) return std::nullopt;
    auto sceneTime = std::filesystem::last_write_time(scene, ec);
    if (!ec && sideTime < sceneTime) return std::nullopt;  // equal: mtime is coarse (jiffies)
    return side;
}

void Document::recoverFrom(const std::filesystem::path& autosave) {
    Scene recovered = loadScene(autosave);
    recovered.path = scene_.path;
    scene_ = std::move(recovered);
    undo_.clear();
    redo_.clear();
    recovered_ = true;
    touched_ |= bit(Command::Touches::Probes) | bit(Command::Touches::Materials);
    ++revision_;
}

// ---- comparison ---------------------------------------------------------------------------

namespace {

bool differ(std::string* why, const std::string& what) {
    if (why) *why = what;
    return false;
}

}  // namespace

bool sameContent(const Scene& a, const Scene& b, std::string* why) {
    if (a.nodes.size() != b.nodes.size())
        return differ(why, "node count " + std::to_string(a.nodes.size()) + " vs " + std::to_string(b.nodes.size()));
    if (a.roots != b.roots) return differ(why, "roots");
    for (size_t i = 0; i < a.nodes.size(); ++i) {
        const Node &x = a.nodes[i], &y = b.nodes[i];
        std::string at = "node " + std::to_string(i) + " (" + x.name + ")";
        if (x.name != y.name) return differ(why, at + ": name");
        if (x.translation != y.translation) return differ(why, at + ": translation");
        if (x.rotation != y.rotation) return differ(why, at + ": rotation");
        if (x.scale != y.scale) return differ(why, at + ": scale");
        if (x.mesh != y.mesh || x.camera != y.camera || x.light != y.light) return differ(why, at + ": references");
        if (x.children != y.children || x.parent != y.parent) return differ(why, at + ": hierarchy");
        if (x.probe != y.probe) return differ(why, at + ": probe");
    }
    if (a.materials.size() != b.materials.size()) return differ(why, "material count");
    for (size_t i = 0; i < a.materials.size(); ++i) {
        const Material &x = a.materials[i], &y = b.materials[i];
        std::string at = "material " + std::to_string(i) + " (" + x.name + ")";
        if (x.name != y.name) return differ(why, at + ": name");
        if (x.baseColor != y.baseColor) return differ(why, at + ": baseColorFactor");
        if (x.metallic != y.metallic) return differ(why, at + ": metallicFactor");
        if (x.roughness != y.roughness) return differ(why, at + ": roughnessFactor");
        if (x.emissive != y.emissive) return differ(why, at + ": emissiveFactor");
        if (x.reflections != y.reflections) return differ(why, at + ": SPECULUM_reflections");
    }
    return true;
}

}  // namespace speculum::editor
