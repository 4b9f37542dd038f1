#include "fields.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace speculum::editor {

std::optional<FieldEdit> fieldWidget(const SettingDesc& d, double value) {
    ImGui::PushID(d.name.c_str());
    std::optional<FieldEdit> edit;
    // The panels group fields by module or object, so the label is the key after the prefix.
    std::string key = d.name.substr(d.name.find('.') + 1);
    std::string label = key + (d.unit.empty() ? "" : " (" + d.unit + ")");
    ImGui::PushItemWidth(ImGui::GetContentRegionAvail().x * 0.5f);
    auto changed = [&](bool valueChanged, double v) {
        bool done = ImGui::IsItemDeactivatedAfterEdit();
        if (valueChanged || done) edit = FieldEdit{v, done};
    };
    if (ImGui::SmallButton("R")) edit = FieldEdit{d.defaultValue, true};
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("reset to the default, %g", d.defaultValue);
    ImGui::SameLine();
    switch (d.type) {
        case SettingType::Bool: {
            bool b = value != 0.0;
            // A checkbox edit is complete when it happens.
            if (ImGui::Checkbox(label.c_str(), &b)) edit = FieldEdit{b ? 1.0 : 0.0, true};
            break;
        }
        case SettingType::Enum: {
            int i = std::clamp(int(value), 0, int(d.choices.size()) - 1);
            if (ImGui::BeginCombo(label.c_str(), d.choices.empty() ? "" : d.choices[size_t(i)].c_str())) {
                for (size_t k = 0; k < d.choices.size(); ++k)
                    if (ImGui::Selectable(d.choices[k].c_str(), int(k) == i)) edit = FieldEdit{double(k), true};
                ImGui::EndCombo();
            }
            break;
        }
        case SettingType::Int: {
            int v = int(value);
            bool wide = d.max - d.min > 4096;
            bool c = wide ? ImGui::DragInt(label.c_str(), &v, 1.0f, int(d.min), int(d.max))
                          : ImGui::SliderInt(label.c_str(), &v, int(d.min), int(d.max));
            changed(c, std::clamp(double(v), d.min, d.max));
            break;
        }
        case SettingType::Float: {
            float v = float(value);
            // Ranges over three decades (exposure) read better on a logarithmic slider.
            ImGuiSliderFlags flags = d.min > 0.0 && d.max / d.min > 1000.0 ? ImGuiSliderFlags_Logarithmic : 0;
            bool c = ImGui::SliderFloat(label.c_str(), &v, float(d.min), float(d.max), "%.3f", flags);
            changed(c, std::clamp(double(v), d.min, d.max));
            break;
        }
    }
    if (ImGui::IsItemHovered() && !d.help.empty()) ImGui::SetTooltip("%s\n(%s)", d.help.c_str(), d.name.c_str());
    ImGui::PopItemWidth();
    ImGui::PopID();
    return edit;
}

// ---- materials ----------------------------------------------------------------------------

const std::vector<SettingDesc>& materialFields() {
    // Ranges and defaults from engine/scene/EXTENSIONS.md (SPECULUM_reflections) and glTF 2.0.
    static const std::vector<SettingDesc> fields = {
        {"material.metallic", SettingType::Float, "", 0, 1, 1, {}, "glTF metallicFactor."},
        {"material.roughness", SettingType::Float, "", 0, 1, 1, {}, "glTF roughnessFactor (perceptual roughness)."},
        {"material.base_r", SettingType::Float, "", 0, 1, 1, {}, "glTF baseColorFactor, red."},
        {"material.base_g", SettingType::Float, "", 0, 1, 1, {}, "glTF baseColorFactor, green."},
        {"material.base_b", SettingType::Float, "", 0, 1, 1, {}, "glTF baseColorFactor, blue."},
        {"reflections.mode",
         SettingType::Enum,
         "",
         0,
         3,
         1,
         {"off", "screen_space", "probes_only", "local_cubemap_only"},
         "SPECULUM_reflections mode: off, the whole chain, probes then sky, or local cubemaps only."},
        {"reflections.roughness_scale",
         SettingType::Float,
         "x",
         0,
         16,
         1,
         {},
         "Multiplies the material's roughness for reflections."},
        {"reflections.has_roughness_override",
         SettingType::Bool,
         "",
         0,
         1,
         0,
         {},
         "Replace the material's roughness for reflections by the override below."},
        {"reflections.roughness_override",
         SettingType::Float,
         "",
         0,
         1,
         0,
         {},
         "The roughness reflections use when the override is on."},
        {"reflections.max_screen_space_roughness",
         SettingType::Float,
         "",
         0,
         1,
         0.6,
         {},
         "Above this roughness, screen-space tracing hands over to the probes and the sky."},
        {"reflections.trace_cmos",
         SettingType::Bool,
         "",
         0,
         1,
         1,
         {},
         "Trace the cubemap objects (CMOs) for this material."},
        {"reflections.mirror_for_self_reflections",
         SettingType::Bool,
         "",
         0,
         1,
         0,
         {},
         "The surface is a mirror for CMO self-reflections."},
    };
    return fields;
}

double materialField(const Material& m, const std::string& n) {
    MaterialReflections r = reflectionsOf(m);
    if (n == "material.metallic") return m.metallic;
    if (n == "material.roughness") return m.roughness;
    if (n == "material.base_r") return m.baseColor.r;
    if (n == "material.base_g") return m.baseColor.g;
    if (n == "material.base_b") return m.baseColor.b;
    if (n == "reflections.mode") return double(r.mode);
    if (n == "reflections.roughness_scale") return r.roughnessScale;
    if (n == "reflections.has_roughness_override") return r.roughnessOverride ? 1.0 : 0.0;
    if (n == "reflections.roughness_override") return r.roughnessOverride.value_or(0.0f);
    if (n == "reflections.max_screen_space_roughness") return r.maxScreenSpaceRoughness;
    if (n == "reflections.trace_cmos") return r.traceCmos ? 1.0 : 0.0;
    if (n == "reflections.mirror_for_self_reflections") return r.mirrorForSelfReflections ? 1.0 : 0.0;
    throw std::logic_error("no material field " + n);
}

void setMaterialField(Material& m, const std::string& n, double v) {
    float f = float(v);
    if (n == "material.metallic")
        m.metallic = f;
    else if (n == "material.roughness")
        m.roughness = f;
    else if (n == "material.base_r")
        m.baseColor.r = f;
    else if (n == "material.base_g")
        m.baseColor.g = f;
    else if (n == "material.base_b")
        m.baseColor.b = f;
    else if (n.rfind("reflections.", 0) == 0) {
        // Editing a reflections field writes the extension (with the effective values).
        MaterialReflections r = reflectionsOf(m);
        if (n == "reflections.mode")
            r.mode = ReflectionMode(std::clamp(int(v), 0, 3));
        else if (n == "reflections.roughness_scale")
            r.roughnessScale = f;
        else if (n == "reflections.has_roughness_override")
            r.roughnessOverride = v != 0.0 ? std::optional<float>(r.roughnessOverride.value_or(0.0f)) : std::nullopt;
        else if (n == "reflections.roughness_override")
            r.roughnessOverride = f;
        else if (n == "reflections.max_screen_space_roughness")
            r.maxScreenSpaceRoughness = f;
        else if (n == "reflections.trace_cmos")
            r.traceCmos = v != 0.0;
        else if (n == "reflections.mirror_for_self_reflections")
            r.mirrorForSelfReflections = v != 0.0;
        else
            throw std::logic_error("no material field " + n);
        m.reflections = r;
    } else {
        throw std::logic_error("no material field " + n);
    }
}

// ---- probes -------------------------------------------------------------------------------

const std::vector<SettingDesc>& probeFields() {
    // engine/scene/EXTENSIONS.md, SPECULUM_reflection_probe.
    static const std::vector<SettingDesc> fields = {
        {"probe.kind",
         SettingType::Enum,
         "",
         0,
         1,
         0,
         {"local_cubemap", "cmo"},
         "A local cubemap, or a cubemap object (CMO) for tracing."},
        {"probe.shape", SettingType::Enum, "", 0, 1, 0, {"box", "sphere"}, "Influence and parallax shape."},
        {"probe.extents_x",
         SettingType::Float,
         "m",
         0.01,
         100,
         1,
         {},
         "Box half-extent along the node's x (sphere: the radius)."},
        {"probe.extents_y", SettingType::Float, "m", 0.01, 100, 1, {}, "Box half-extent along the node's y."},
        {"probe.extents_z", SettingType::Float, "m", 0.01, 100, 1, {}, "Box half-extent along the node's z."},
        {"probe.blend_distance",
         SettingType::Float,
         "m",
         0,
         10,
         0.5,
         {},
         "Width of the fade at the influence's border."},
        {"probe.resolution",
         SettingType::Enum,
         "px",
         0,
         6,
         4,
         {"8", "16", "32", "64", "128", "256", "512"},
         "Cubemap face size in texels."},
        {"probe.update",
         SettingType::Enum,
         "",
         0,
         3,
         0,
         {"once", "on_demand", "every_frame", "time_sliced"},
         "When the probe captures: once at start, when asked, every frame, or one face per frame."},
        {"probe.order", SettingType::Int, "", -100, 100, 0, {}, "Higher wins where probes overlap."},
    };
    return fields;
}

double probeField(const ReflectionProbe& p, const std::string& n) {
    if (n == "probe.kind") return double(p.kind);
    if (n == "probe.shape") return double(p.shape);
    if (n == "probe.extents_x") return p.extents.x;
    if (n == "probe.extents_y") return p.extents.y;
    if (n == "probe.extents_z") return p.extents.z;
    if (n == "probe.blend_distance") return p.blendDistance;
    if (n == "probe.resolution") return std::log2(double(std::max(8u, p.resolution))) - 3.0;
    if (n == "probe.update") return double(p.update);
    if (n == "probe.order") return p.order;
    throw std::logic_error("no probe field " + n);
}

void setProbeField(ReflectionProbe& p, const std::string& n, double v) {
    if (n == "probe.kind")
        p.kind = ProbeKind(std::clamp(int(v), 0, 1));
    else if (n == "probe.shape")
        p.shape = ProbeShape(std::clamp(int(v), 0, 1));
    else if (n == "probe.extents_x")
        p.extents.x = float(v);
    else if (n == "probe.extents_y")
        p.extents.y = float(v);
    else if (n == "probe.extents_z")
        p.extents.z = float(v);
    else if (n == "probe.blend_distance")
        p.blendDistance = float(v);
    else if (n == "probe.resolution")
        p.resolution = 8u << std::clamp(int(v), 0, 6);
    else if (n == "probe.update")
        p.update = ProbeUpdate(std::clamp(int(v), 0, 3));
    else if (n == "probe.order")
        p.order = int(v);
    else
        throw std::logic_error("no probe field " + n);
}

}  // namespace speculum::editor
