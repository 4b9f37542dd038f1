// Widgets generated from SettingDesc tables (name, unit, range, default, help as tooltip, reset
// to default), and the tables of the per-object fields the inspector edits (a material's base
// PBR factors and SPECULUM_reflections, a probe's SPECULUM_reflection_probe): every field is
// described once, here or in its module's settings table, and drawn by the same function.
#pragma once

#include "speculum/scene.hpp"
#include "speculum/settings.hpp"

#include <optional>
#include <string>
#include <vector>

namespace speculum::editor {

// Draws one widget for `desc` showing `value`. Returns the new value while the user edits it
// (`committed` false) and once more when the edit ends (`committed` true): the caller previews
// the first and turns the second into one command.
struct FieldEdit {
    double value = 0.0;
    bool committed = false;
};
std::optional<FieldEdit> fieldWidget(const SettingDesc& desc, double value);

// The material fields the inspector shows: "material.roughness", "reflections.mode", ...
const std::vector<SettingDesc>& materialFields();
double materialField(const Material& m, const std::string& name);
void setMaterialField(Material& m, const std::string& name, double value);

// The probe fields: "probe.extents_x", "probe.blend_distance", ...
const std::vector<SettingDesc>& probeFields();
double probeField(const ReflectionProbe& p, const std::string& name);
void setProbeField(ReflectionProbe& p, const std::string& name, double value);

}  // namespace speculum::editor
