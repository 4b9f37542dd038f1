#include "speculum/app/engine_settings.hpp"

namespace speculum::app {

std::vector<SettingDesc> engineSettingsTable() { return render::RendererOptions::fields().descs(); }

}  // namespace speculum::app
