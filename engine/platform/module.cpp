#include "speculum/app/module.hpp"

#include <algorithm>

namespace speculum::app {

std::vector<SettingDesc> settingsOf(std::vector<SettingDesc> engine, const std::vector<ModuleInfo>& modules) {
    for (const ModuleInfo& m : modules) engine.insert(engine.end(), m.settings.begin(), m.settings.end());
    return engine;
}

const ModuleInfo* aovProvider(const std::vector<ModuleInfo>& modules, const std::string& name) {
    for (const ModuleInfo& m : modules)
        if (std::any_of(m.aovs.begin(), m.aovs.end(), [&](const AovInfo& a) { return a.name == name; })) return &m;
    return nullptr;
}

std::vector<std::string> debugViews(const ModuleInfo& module) {
    for (const SettingDesc& d : module.settings)
        if (d.name == module.debugViewSetting) return d.choices;
    return {};
}

}  // namespace speculum::app
