// The seam between the engine and its modules (docs/design.md section 4, modules). A module tells its host
// what it is (ModuleInfo: its settings table, the AOVs it can provide, its debug views); the host
// (capture, game, editor, bench) registers that with its FrameRunner and composes the modules in
// order in a LitHook, handing one module's typed output handles to the next (probes ->
// reflections). The engine's platform layer knows no module by name: it learns names, AOVs and
// settings from what is registered.
#pragma once

#include "speculum/settings.hpp"

#include <string>
#include <vector>

namespace speculum::app {

struct AovInfo {
    std::string name;  // --aov NAME, and the file name NAME.FFFF.exr
    std::string help;
};

struct ModuleInfo {
    std::string name;                  // "reflections"
    std::vector<SettingDesc> settings; // its table (the one description of each setting)
    std::vector<AovInfo> aovs;         // AOVs it provides on the frames it runs
    std::string debugViewSetting;      // the Enum setting that picks its debug view ("" none)
    // Named in the message when its AOVs are asked for on a frame it does not run.
    std::string enableSetting;
};

// Every setting of the engine and the given modules, in order (for Settings and --help).
std::vector<SettingDesc> settingsOf(std::vector<SettingDesc> engine, const std::vector<ModuleInfo>& modules);
// The module that provides AOV `name`, or null.
const ModuleInfo* aovProvider(const std::vector<ModuleInfo>& modules, const std::string& name);
// The debug views of a module: the choices of its debugViewSetting.
std::vector<std::string> debugViews(const ModuleInfo& module);

}  // namespace speculum::app
