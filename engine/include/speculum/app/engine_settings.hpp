// The engine's own settings (render.*, bound to render::RendererOptions: fill the options with
// fromSettings<render::RendererOptions>()); modules append their tables.
#pragma once

#include "speculum/render/renderer.hpp"
#include "speculum/settings.hpp"

namespace speculum::app {

std::vector<SettingDesc> engineSettingsTable();

}  // namespace speculum::app
