#include "fields.hpp"

#include <imgui.h>

#include <algorithm>
#include <array>
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

// ---- materials and probes ------------------------------------------------------------------
// One row a field: its description and where it lives (a member, or a read and a write where the
// value is not one member's, such as an optional's presence or a resolution's log2).

namespace {

template <size_t N>
std::vector<std::string> choices(const std::array<const char*, N>& names) {
    return {names.begin(), names.end()};
}

template <class T>
const SettingField<T>& rowNamed(const SettingFields<T>& fields, const std::string& name, const char* kind) {
    for (const SettingField<T>& row : fields.rows())
        if (row.desc.name == name) return row;
    throw std::logic_error(std::string("no ") + kind + " field " + name);
}

// Editing a reflections field writes the extension, with the effective values of the others.
SettingField<Material> onReflections(SettingField<MaterialReflections> row) {
    return {row.desc, nullptr,
            [write = row.write](Material& m, double v) {
                MaterialReflections r = reflectionsOf(m);
                write(r, v);
                m.reflections = r;
            },
            [read = row.read](const Material& m) { return read(reflectionsOf(m)); }};
}

const SettingFields<Material>& materialTable() {
    using T = SettingType;
    using R = MaterialReflections;
    auto base = [](SettingDesc d, auto access) { return bindAccess<Material>(std::move(d), access); };
    auto refl = [](SettingDesc d, auto access) { return onReflections(bindAccess<R>(std::move(d), access)); };
    // Ranges and defaults from engine/scene/EXTENSIONS.md (SPECULUM_reflections) and glTF 2.0.
    static const SettingFields<Material> table({
        base({"material.metallic", T::Float, "", 0, 1, 1, {}, "glTF metallicFactor."},
             [](auto& m) -> auto& { return m.metallic; }),
        base({"material.roughness", T::Float, "", 0, 1, 1, {}, "glTF roughnessFactor (perceptual roughness)."},
             [](auto& m) -> auto& { return m.roughness; }),
        base({"material.base_r", T::Float, "", 0, 1, 1, {}, "glTF baseColorFactor, red."},
             [](auto& m) -> auto& { return m.baseColor.r; }),
        base({"material.base_g", T::Float, "", 0, 1, 1, {}, "glTF baseColorFactor, green."},
             [](auto& m) -> auto& { return m.baseColor.g; }),
        base({"material.base_b", T::Float, "", 0, 1, 1, {}, "glTF baseColorFactor, blue."},
             [](auto& m) -> auto& { return m.baseColor.b; }),
        refl({"reflections.mode", T::Enum, "", 0, 3, 1, choices(kReflectionModeNames),
              "SPECULUM_reflections mode: off, the whole chain, probes then sky, or local cubemaps only."},
             [](auto& r) -> auto& { return r.mode; }),
        refl({"reflections.roughness_scale", T::Float, "x", 0, 16, 1, {},
              "Multiplies the material's roughness for reflections."},
             [](auto& r) -> auto& { return r.roughnessScale; }),
        onReflections({{"reflections.has_roughness_override", T::Bool, "", 0, 1, 0, {},
                        "Replace the material's roughness for reflections by the override below."},
                       nullptr,
                       [](R& r, double v) {
                           r.roughnessOverride =
                               v != 0.0 ? std::optional<float>(r.roughnessOverride.value_or(0.0f)) : std::nullopt;
                       },
                       [](const R& r) { return r.roughnessOverride ? 1.0 : 0.0; }}),
        onReflections({{"reflections.roughness_override", T::Float, "", 0, 1, 0, {},
                        "The roughness reflections use when the override is on."},
                       nullptr,
                       [](R& r, double v) { r.roughnessOverride = float(v); },
                       [](const R& r) { return double(r.roughnessOverride.value_or(0.0f)); }}),
        refl({"reflections.max_screen_space_roughness", T::Float, "", 0, 1, 0.6, {},
              "Above this roughness, screen-space tracing hands over to the probes and the sky."},
             [](auto& r) -> auto& { return r.maxScreenSpaceRoughness; }),
        refl({"reflections.trace_cmos", T::Bool, "", 0, 1, 1, {}, "Trace the cubemap objects (CMOs) for this material."},
             [](auto& r) -> auto& { return r.traceCmos; }),
        refl({"reflections.mirror_for_self_reflections", T::Bool, "", 0, 1, 0, {},
              "The surface is a mirror for CMO self-reflections."},
             [](auto& r) -> auto& { return r.mirrorForSelfReflections; }),
    });
    return table;
}

const SettingFields<ReflectionProbe>& probeTable() {
    using T = SettingType;
    using P = ReflectionProbe;
    // engine/scene/EXTENSIONS.md, SPECULUM_reflection_probe.
    static const SettingFields<P> table({
        bind<&P::kind>({"probe.kind", T::Enum, "", 0, 2, 0, choices(kProbeKindNames),
                        "A local cubemap, a cubemap object (CMO) for tracing, or a planar probe (a flat mirror)."}),
        bind<&P::shape>({"probe.shape", T::Enum, "", 0, 1, 0, choices(kProbeShapeNames), "Influence and parallax shape."}),
        bindAccess<P>({"probe.extents_x", T::Float, "m", 0.01, 100, 1, {},
                       "Box half-extent along the node's x (sphere: the radius; planar: the half width)."},
                      [](auto& p) -> auto& { return p.extents.x; }),
        bindAccess<P>({"probe.extents_y", T::Float, "m", 0.01, 100, 1, {},
                       "Box half-extent along the node's y (planar: the half depth along the node's z)."},
                      [](auto& p) -> auto& { return p.extents.y; }),
        bindAccess<P>({"probe.extents_z", T::Float, "m", 0.01, 100, 1, {}, "Box half-extent along the node's z."},
                      [](auto& p) -> auto& { return p.extents.z; }),
        bind<&P::blendDistance>({"probe.blend_distance", T::Float, "m", 0, 10, 0.5, {},
                                 "Width of the fade at the influence's border."}),
        {{"probe.resolution", T::Enum, "px", 0, 6, 4, {"8", "16", "32", "64", "128", "256", "512"},
          "Cubemap face size in texels; a planar probe's image height (8: half the view's)."},
         nullptr,
         // A planar probe's height is at least 16 px: the first choice stands for its default (0).
         [](P& p, double v) {
             int i = std::clamp(int(v), 0, 6);
             p.resolution = p.kind == ProbeKind::Planar && i == 0 ? 0u : 8u << i;
         },
         [](const P& p) { return std::log2(double(std::max(8u, p.resolution))) - 3.0; }},
        bind<&P::update>({"probe.update", T::Enum, "", 0, 3, 0, choices(kProbeUpdateNames),
                          "When the probe captures: once at start, when asked, every frame, or one face per frame."}),
        bind<&P::order>({"probe.order", T::Int, "", -100, 100, 0, {}, "Higher wins where probes overlap."}),
    });
    return table;
}

}  // namespace

const std::vector<SettingDesc>& materialFields() {
    static const std::vector<SettingDesc> descs = materialTable().descs();
    return descs;
}

double materialField(const Material& m, const std::string& name) {
    return rowNamed(materialTable(), name, "material").read(m);
}

void setMaterialField(Material& m, const std::string& name, double value) {
    rowNamed(materialTable(), name, "material").write(m, value);
}

const std::vector<SettingDesc>& probeFields() {
    static const std::vector<SettingDesc> descs = probeTable().descs();
    return descs;
}

double probeField(const ReflectionProbe& p, const std::string& name) { return rowNamed(probeTable(), name, "probe").read(p); }

void setProbeField(ReflectionProbe& p, const std::string& name, double value) {
    rowNamed(probeTable(), name, "probe").write(p, value);
}

}  // namespace speculum::editor
