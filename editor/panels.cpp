// The ImGui panels: menu bar, outliner, inspector, settings, frame graph. Every edit they make
// goes through the command functions of app.cpp, as the script's do.
#include "app.hpp"

#include "fields.hpp"

#include "speculum/app/module.hpp"
#include "speculum/core.hpp"

#include <imgui.h>

#include <algorithm>
#include <functional>
#include <set>

namespace speculum::editor {

namespace {

std::string nodeLabel(const Node& n, size_t index) {
    std::string label = n.name.empty() ? "node " + std::to_string(index) : n.name;
    if (n.probe)
        label += n.probe->kind == ProbeKind::Cmo ? "  [CMO]" : n.probe->kind == ProbeKind::Planar ? "  [planar]" : "  [probe]";
    if (n.camera >= 0) label += "  [camera]";
    if (n.light >= 0) label += "  [light]";
    return label;
}

// The materials the node's mesh draws with (-1: glTF's default material).
std::vector<int> materialsOf(const Scene& s, int node) {
    std::set<int> out;
    const Node& n = s.nodes[size_t(node)];
    if (n.mesh >= 0)
        for (const Primitive& p : s.meshes[size_t(n.mesh)].primitives) out.insert(p.material);
    return {out.begin(), out.end()};
}

}  // namespace

void EditorApp::drawMenuBar() {
    if (!ImGui::BeginMainMenuBar()) return;
    if (ImGui::BeginMenu("File")) {
        if (ImGui::MenuItem("Save", "Ctrl+S")) save();
        ImGui::InputText("##saveas", saveAsBuffer_, sizeof saveAsBuffer_);
        ImGui::SameLine();
        if (ImGui::Button("Save as")) saveAs(saveAsBuffer_);
        if (ImGui::MenuItem("Quit")) quit_ = true;
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Edit")) {
        if (ImGui::MenuItem(("Undo " + doc_.undoName()).c_str(), "Ctrl+Z", false, doc_.canUndo())) undo();
        if (ImGui::MenuItem(("Redo " + doc_.redoName()).c_str(), "Ctrl+Shift+Z", false, doc_.canRedo())) redo();
        ImGui::Separator();
        if (ImGui::MenuItem("Add probe at the picked point", nullptr, false, pick_.hit)) addProbeAtPick();
        if (ImGui::MenuItem("Add CMO at the picked point", nullptr, false, pick_.hit)) addProbeAtPick(ProbeKind::Cmo);
        if (ImGui::MenuItem("Add planar probe on the picked surface", nullptr, false, pick_.hit))
            addProbeAtPick(ProbeKind::Planar);
        if (ImGui::MenuItem("Delete probe", "Del")) deleteSelectedProbe();
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("View")) {
        for (const Camera& c : doc_.scene().cameras)
            if (ImGui::MenuItem(("Camera " + c.name).c_str(), nullptr, camera_.named() == c.name)) camera_.useNamed(c);
        ImGui::Separator();
        if (ImGui::MenuItem("Frame selection", "F")) frameSelection();
        ImGui::MenuItem("Pixel inspector", nullptr, &pixelInspector_);
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Debug view")) {
        // Every module's debug views, from what it registered (ModuleInfo::debugViewSetting).
        for (const app::ModuleInfo& m : chain::moduleInfos()) {
            if (m.debugViewSetting.empty() || !ImGui::BeginMenu(m.name.c_str())) continue;
            std::vector<std::string> views = app::debugViews(m);
            int current = doc_.settings().getInt(m.debugViewSetting);
            for (size_t i = 0; i < views.size(); ++i)
                if (ImGui::MenuItem(views[i].c_str(), nullptr, int(i) == current))
                    setDebugView(m.debugViewSetting, double(i));
            ImGui::EndMenu();
        }
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Probes")) {
        if (ImGui::MenuItem("Bake all")) viewport_->requestBake(-1);
        ImGui::Text("%zu faces captured so far", viewport_->probes().facesCaptured());
        ImGui::EndMenu();
    }
    ImGui::Separator();
    ImGui::TextUnformatted((doc_.path().filename().string() + (doc_.dirty() ? " *" : "")).c_str());
    ImGui::Separator();
    ImGui::TextUnformatted(status_.c_str());
    ImGui::EndMainMenuBar();
}

void EditorApp::drawOutliner() {
    const Scene& s = doc_.scene();
    // The scene's named cameras, one click away.
    float right = ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x;
    for (size_t i = 0; i < s.cameras.size(); ++i) {
        const Camera& c = s.cameras[i];
        bool on = camera_.named() == c.name;
        if (on) ImGui::PushStyleColor(ImGuiCol_Button, ImGui::GetStyleColorVec4(ImGuiCol_ButtonActive));
        if (ImGui::SmallButton(c.name.c_str())) camera_.useNamed(c);
        if (on) ImGui::PopStyleColor();
        // The next button on this line when it fits, else on the next (the row wraps).
        float next = i + 1 < s.cameras.size() ? ImGui::CalcTextSize(s.cameras[i + 1].name.c_str()).x + 24.0f : 0.0f;
        if (i + 1 < s.cameras.size() && ImGui::GetItemRectMax().x + next < right) ImGui::SameLine();
    }
    ImGui::Separator();
    std::function<void(int)> tree = [&](int i) {
        const Node& n = s.nodes[size_t(i)];
        ImGuiTreeNodeFlags flags = ImGuiTreeNodeFlags_OpenOnArrow | ImGuiTreeNodeFlags_SpanAvailWidth;
        if (n.children.empty()) flags |= ImGuiTreeNodeFlags_Leaf | ImGuiTreeNodeFlags_NoTreePushOnOpen;
        if (i == selectedNode_) flags |= ImGuiTreeNodeFlags_Selected;
        if (n.probe) ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(80, 220, 230, 255));
        bool open =
            ImGui::TreeNodeEx(reinterpret_cast<void*>(intptr_t(i)), flags, "%s", nodeLabel(n, size_t(i)).c_str());
        if (n.probe) ImGui::PopStyleColor();
        if (ImGui::IsItemClicked()) select(i);
        if (open && !n.children.empty()) {
            for (int c : n.children) tree(c);
            ImGui::TreePop();
        }
    };
    for (int r : s.roots) tree(r);
}

void EditorApp::drawInspector() {
    const Scene& s = doc_.scene();
    if (pick_.hit) {
        ImGui::Text("pick: %.2f %.2f %.2f", pick_.position.x, pick_.position.y, pick_.position.z);
        ImGui::SameLine();
        if (ImGui::SmallButton("Add probe here")) addProbeAtPick();
        ImGui::SameLine();
        if (ImGui::SmallButton("Add CMO here")) addProbeAtPick(ProbeKind::Cmo);
        ImGui::SameLine();
        if (ImGui::SmallButton("Add planar here")) addProbeAtPick(ProbeKind::Planar);
    }
    if (pixelInspector_) {
        const PixelInfo& p = viewport_->lastPixel();
        if (!p.valid) {
            ImGui::TextDisabled("pixel inspector: hover the viewport (reflections on)");
        } else {
            ImGui::Text("pixel: method ss %.2f probes %.2f sky %.2f", p.method.x, p.method.y, p.method.z);
            ImGui::Text("iterations %.0f, roughness %.3f", p.iterations, p.roughness);
            ImGui::Text("reflection %.3f %.3f %.3f", p.reflection.x, p.reflection.y, p.reflection.z);
        }
    }
    ImGui::Separator();
    if (selectedNode_ < 0) {
        ImGui::TextWrapped("Click a surface in the viewport, or a node in the outliner.");
        return;
    }
    const Node& n = s.nodes[size_t(selectedNode_)];
    ImGui::Text("%s", nodeLabel(n, size_t(selectedNode_)).c_str());
    glm::vec3 p(n.world[3]);
    ImGui::Text("world position %.3f %.3f %.3f", p.x, p.y, p.z);
    if (n.probe) {
        ImGui::Separator();
        ImGui::TextUnformatted("SPECULUM_reflection_probe");
        for (const SettingDesc& d : probeFields())
            if (auto e = fieldWidget(d, probeField(*n.probe, d.name)); e && e->committed)
                setProbeValue(selectedNode_, d.name, e->value);
        if (ImGui::Button("Bake")) {
            const auto& infos = viewport_->probes().probes();
            for (size_t i = 0; i < infos.size(); ++i)
                if (infos[i].node == selectedNode_) viewport_->requestBake(int(i));
        }
        ImGui::SameLine();
        if (ImGui::Button("Bake all")) viewport_->requestBake(-1);
        ImGui::SameLine();
        if (ImGui::Button("Delete probe")) deleteSelectedProbe();
        return;
    }
    for (int m : materialsOf(s, selectedNode_)) {
        if (m < 0 || size_t(m) >= s.materials.size()) {
            ImGui::TextDisabled("glTF default material (not editable)");
            continue;
        }
        const Material& mat = s.materials[size_t(m)];
        ImGui::PushID(m);
        if (ImGui::CollapsingHeader(("material " + mat.name).c_str(), ImGuiTreeNodeFlags_DefaultOpen))
            for (const SettingDesc& d : materialFields()) {
                auto e = fieldWidget(d, materialField(mat, d.name));
                if (!e) continue;
                // Base PBR factors are previewed while the slider moves (the renderer re-reads
                // them); the edit becomes one command when it is let go.
                bool factor = d.name.rfind("material.", 0) == 0;
                if (!e->committed && factor) {
                    if (!materialBefore_) materialBefore_ = std::make_pair(m, mat);
                    setMaterialField(doc_.mutableScene().materials[size_t(m)], d.name, e->value);
                    viewport_->previewMaterials();
                    continue;
                }
                if (!e->committed) continue;
                if (materialBefore_ && materialBefore_->first == m) {
                    doc_.mutableScene().materials[size_t(m)] = materialBefore_->second;
                    materialBefore_.reset();
                }
                setMaterialValue(m, d.name, e->value);
            }
        ImGui::PopID();
    }
}

void EditorApp::drawSettings() {
    // Generated from the engine's and the modules' tables, grouped by module.
    std::string group;
    bool open = false;
    for (const SettingDesc& d : doc_.settings().table()) {
        std::string g = d.name.substr(0, d.name.find('.'));
        if (g != group) {
            group = g;
            open = ImGui::CollapsingHeader(g.c_str(), ImGuiTreeNodeFlags_DefaultOpen);
        }
        if (!open) continue;
        auto e = fieldWidget(d, doc_.settings().get(d.name));
        if (!e) continue;
        if (d.name.find(".debug_") != std::string::npos) {  // view state, as in the Debug view menu
            setDebugView(d.name, e->value);
            continue;
        }
        if (!e->committed) {
            // Previewed while the slider moves (the modules read settings every frame); one
            // command when it is let go.
            editing_.try_emplace(d.name, doc_.settings().get(d.name));
            doc_.mutableSettings().set(d.name, e->value);
            continue;
        }
        if (auto it = editing_.find(d.name); it != editing_.end()) {
            doc_.mutableSettings().set(d.name, it->second);
            editing_.erase(it);
        }
        setSettingValue(d.name, e->value);
    }
}

void EditorApp::drawFrameGraph() {
    static auto lastDump = std::chrono::steady_clock::time_point{};
    if (std::chrono::steady_clock::now() - lastDump > std::chrono::seconds(1)) {
        graph_ = nlohmann::json::parse(viewport_->graphJson(), nullptr, false);
        lastDump = std::chrono::steady_clock::now();
    }
    if (std::chrono::steady_clock::now() - shownAt_ > std::chrono::seconds(1)) {
        shownAt_ = std::chrono::steady_clock::now();
        shownPasses_ = passTimes_;
        shownGpuMs_ = gpuMs_;
        shownUiMs_ = uiMs_;
    }
    double maxMs = 0.0;
    for (const app::PassTime& p : shownPasses_) maxMs = std::max(maxMs, p.ms);
    ImGui::Text("GPU %.1f ms (UI and viewport blit %.2f ms, %.1f%%)", shownGpuMs_, shownUiMs_,
                shownGpuMs_ > 0 ? 100.0 * shownUiMs_ / shownGpuMs_ : 0.0);
    if (graph_.is_object() && graph_.contains("memory")) {
        double with = graph_["memory"].value("transientWithAliasing", 0.0) / 1048576.0;
        double without = graph_["memory"].value("transientWithoutAliasing", 0.0) / 1048576.0;
        ImGui::SameLine();
        ImGui::Text("  transient peak %.1f MB (%.1f MB without aliasing)", with, without);
    }
    ImGui::Columns(2, "fg", true);
    ImGui::SetColumnWidth(0, std::max(200.0f, ImGui::GetWindowWidth() * 0.55f));
    for (const app::PassTime& p : shownPasses_) {
        char label[64];
        std::snprintf(label, sizeof label, "%.2f ms", p.ms);
        ImGui::ProgressBar(maxMs > 0 ? float(p.ms / maxMs) : 0.0f, ImVec2(120, 0), label);
        ImGui::SameLine();
        ImGui::TextUnformatted(p.name.c_str());
    }
    ImGui::NextColumn();
    // Resources: size, and where aliasing placed a transient in the shared heap.
    if (graph_.is_object() && graph_.contains("textures"))
        for (const auto& t : graph_["textures"]) {
            std::string where = t.value("imported", false) ? "imported" : "culled";
            if (t.contains("placement") && t["placement"].is_object())
                where = std::to_string(t["placement"].value("size", 0ull) >> 10) + " KB @" +
                        std::to_string(t["placement"].value("offset", 0ull) >> 10) + " KB";
            ImGui::Text("%s %sx%s m%s l%s  %s", t.value("name", "").c_str(), t["width"].dump().c_str(),
                        t["height"].dump().c_str(), t["mips"].dump().c_str(), t["layers"].dump().c_str(),
                        where.c_str());
        }
    ImGui::Columns(1);
}

void EditorApp::drawRecoverPopup() {
    if (!recoverOffer_) return;
    ImGui::OpenPopup("Recover autosave?");
    if (ImGui::BeginPopupModal("Recover autosave?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::Text("%s is newer than the scene you opened.", recoverOffer_->string().c_str());
        if (ImGui::Button("Recover it")) {
            try {
                doc_.recoverFrom(*recoverOffer_);
                status_ = "recovered " + recoverOffer_->string();
            } catch (const Error& e) {
                status_ = e.what();
            }
            recoverOffer_.reset();
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Keep the scene")) {
            recoverOffer_.reset();
            ImGui::CloseCurrentPopup();
        }
        ImGui::EndPopup();
    }
}

}  // namespace speculum::editor
