// The engine's own settings (render.*); modules append their tables.
#pragma once

#include "speculum/render/renderer.hpp"
#include "speculum/settings.hpp"

namespace speculum::app {

std::vector<SettingDesc> engineSettingsTable();
// Copies the render.* values into renderer options.
void applyRenderSettings(const Settings& settings, render::RendererOptions& options);

}  // namespace speculum::app
